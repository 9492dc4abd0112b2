#pragma once
// The pulse detector alone, on synthetic pulses whose truth is known: how often a pulse it lets
// through to the tracks (SignalSeparator::unseparable false) holds the field of one transmitter,
// within its stated noise. A control and two arrangements that the multiple-burial evaluation
// found hard:
//  - kSingle: one transmitter alone (its error should be its stated noise: about 1 sigma);
//  - kNestedPair: two transmitters 0.5-3 Hz apart (one carrier cell), one pulse inside the
//    other or sharing its end, as a pair in lockstep gives at every pulse;
//  - kTogether: four transmitters on carriers 12-84 Hz apart pulsing together (one period,
//    starts within +-4 ms);
//  - kLockstepPair: two transmitters within 1.5 Hz whose pulses overlap as the evaluation's
//    lockstep pairs do: on-times 70-200 ms each, starts within +-0.3 on-times of each other.
// Amplitudes 40-70 dB above the long axis's noise, the second transmitter of a nested pair 0 to
// -15 dB of the first. `sarloc-eval detector` prints it (docs/estimation/avalanche.md).
//
//   DetectorBenchResult r = run_detector_bench(DetectorBenchSetup{});
#include <cstdint>
#include <functional>
#include <vector>

#include "sarloc/core/avalanche/pulse_detector.hpp"
#include "sarloc/core/avalanche/signal_separator.hpp"

namespace sarloc::avalanche {

enum class DetectorScenario : std::uint8_t { kSingle, kNestedPair, kTogether, kLockstepPair };
const char* to_string(DetectorScenario scenario);

struct DetectorBenchSetup {
  DetectorScenario scenario = DetectorScenario::kNestedPair;
  std::uint32_t draws = 200;
  std::uint64_t seed = 1;
  SeparatorConfig separator;  ///< its detector, and what it lets through

  /// Throws ConfigError "detector_bench.<key> = value: rule".
  void validate() const;
};

struct DetectorBenchResult {
  std::uint32_t draws = 0;
  std::uint32_t transmitters = 0;
  std::uint32_t pulses = 0;         ///< detected
  std::uint32_t spurious = 0;       ///< detected, no transmitter within 3 Hz overlapping it
  std::uint32_t let_through = 0;    ///< neither blended, nor too inflated, nor elliptical
  std::uint32_t let_through_spurious = 0;
  /// Per pulse let through and matched to a transmitter: its amplitude error, RMS over the six
  /// real components in units of its stated noise (1 for an honest noise), sorted.
  std::vector<double> error_sigma;
  std::uint32_t beyond_10_sigma = 0;
  std::uint32_t beyond_50_sigma = 0;
  /// The same pulses' error relative to the transmitter's field, |error| / |field|, sorted: the
  /// filter's own model allows 5 % plus the device's calibration (SogConfig, ReceiverModelConfig).
  std::vector<double> error_relative;
  std::uint32_t beyond_5_percent = 0;
  /// Of the matched pulses let through: median |carrier error| (Hz), share with both edges exact.
  double carrier_error_median_hz = 0.0;
  double edges_exact_share = 0.0;
};

/// `on_draw` (optional) after every window, e.g. a progress bar; `cancelled` (optional) is asked
/// before every window, and the result holds the windows run until it said yes.
DetectorBenchResult run_detector_bench(const DetectorBenchSetup& setup, const std::function<void()>& on_draw = {},
                                       const std::function<bool()>& cancelled = {});

}  // namespace sarloc::avalanche
