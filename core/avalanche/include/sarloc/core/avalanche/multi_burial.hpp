#pragma once
// Monte Carlo evaluation of multiple burials with the realistic receiver (issue 12): N
// transmitters within a few metres of one another, pulse periods chosen so that their pulses
// overlap for long stretches, one rescuer whose device separates the signals
// (SignalSeparator) and searches them one after the other (RescuerSearch: one SOG filter per
// signal, the strongest unfound signal next).
//
// Per trial: victims found (a FOUND within its stated 95 % radius + kFalseFoundMarginM of a
// victim not found before: the signal's own transmitter, the one most of its samples came from,
// if it is within that reach, else the nearest victim that is), ghosts (a FOUND near no victim), duplicates (a FOUND of a victim
// already found: reported twice), wrong attributions (pulses the separation gave to a signal
// that was another transmitter's), steps (1 s each) and distance walked until all were found.
//
//   MultiBurialSetup setup;  setup.victims = 3;  setup.spread_m = 5.0;
//   MultiBurialSummary s = run_multi_burial(setup, [&] { bar.tick(); });
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "sarloc/core/avalanche/evaluation.hpp"
#include "sarloc/core/avalanche/pulse_train.hpp"
#include "sarloc/core/avalanche/rescuer_search.hpp"

namespace sarloc::avalanche {

struct MultiBurialSetup {
  SimulationConfig simulation;     ///< the receiver must be realistic
  RescuerSearchConfig rescuer;
  EvaluationConfig evaluation;     ///< trials, seed, threads, step_budget
  std::uint32_t victims = 3;
  double spread_m = 5.0;           ///< every victim within this of every other
  /// Periods of all victims within +-this fraction of a common one: their pulses overlap for
  /// long stretches (0 = independent draws within the standard).
  double period_spread = 0.01;
  void validate() const;
};

/// About 1 / on-time: two carriers this close fall in one frequency cell of the detector.
inline constexpr double kCarrierCellHz = 10.0;

/// A second pulse with a tenth of the energy adds up to a third to the amplitude. Measured on
/// 4 victims seed 11 (10 trials traced): samples mixed below this fit their transmitter's field
/// as clean ones do (1 % beyond 9 per axis of truth NIS), those above it do not (14-42 %).
inline constexpr double kMixedEnergyRatio = 0.1;

/// One FOUND against the victim it was matched to (else the nearest), for consistency by depth.
struct FoundRecord {
  std::uint32_t step = 0;
  double depth_m = 0.0;      ///< that victim's depth below the snow surface
  double range_m = 0.0;      ///< antenna to that victim when FOUND was declared
  double error_m = 0.0;      ///< FOUND position to that victim (3-D)
  double radius95_m = 0.0;   ///< the FOUND's stated 95 % 3-D radius
  double nees = 0.0;         ///< error' P^-1 error (3 degrees of freedom)
  bool ghost = false;        ///< matched to no victim
};

struct MultiBurialTrial {
  std::uint32_t index = 0;
  std::uint32_t found = 0;          ///< distinct victims found correctly
  bool all_found = false;
  std::uint32_t ghosts = 0;
  std::uint32_t duplicates = 0;
  /// FOUNDs made, and of those, the ones whose victim (the one matched to it, else the nearest)
  /// lies outside the 95 % radius the FOUND stated: an honest radius leaves about 5 %.
  std::uint32_t founds = 0;
  std::uint32_t founds_outside_radius = 0;
  /// The largest distance to that victim over the stated 95 % radius (1: on the radius).
  double worst_found_error_to_radius = 0.0;
  std::vector<FoundRecord> found_records;
  /// Signals the device published LOCATED at some epoch (a confirmation incident command shows
  /// as a victim), and of those, the ones whose LOCATED estimate once lay farther than
  /// found_reach from every victim: a victim confirmed where none is. With the largest antenna
  /// to estimate distance at which such a false LOCATED was published.
  std::uint32_t located_signals = 0;
  std::uint32_t false_located = 0;
  double worst_false_located_range_m = 0.0;
  /// Antenna to estimate when each LOCATED signal was first published LOCATED (m).
  std::vector<double> first_located_range_m;
  /// Signals retired as confirmed repeats of a found one (RescuerSearchConfig::same_transmitter_*),
  /// and of those, how many carried mostly another transmitter than the victim found (a victim
  /// the test hid).
  std::uint32_t repeats_retired = 0;
  std::uint32_t repeats_wrong = 0;
  /// Signals ever published as a suspected repeat. A trial with none ran exactly as it would
  /// without the test.
  std::uint32_t repeats_suspected = 0;
  /// Filters rebuilt by the leap test (SogConfig::leap_gate_probability).
  std::uint32_t leaps = 0;
  /// Filters rebuilt after converging on no plausible transmitter (SogConfig::implausible_rebuild_steps).
  std::uint32_t implausible_rebuilds = 0;
  /// FOUNDs withdrawn because their witness filter converged elsewhere
  /// (RescuerSearchConfig::found_witness_window_s).
  std::uint32_t withdrawn_founds = 0;
  /// Times a signal's search walked the primary line again, the device hearing nothing
  /// (SearchConfig::lost_signal_steps).
  std::uint32_t line_resumptions = 0;
  /// FOUND claims that waited for the witness to locate the victim too.
  std::uint32_t deferred_founds = 0;
  std::uint32_t wrong_attributions = 0;
  std::uint32_t unattributed_pulses = 0;
  /// Truth: samples handed to a filter whose pulse held another transmitter's overlapping pulse
  /// on its carrier with at least kMixedEnergyRatio of its energy (two fields summed into one
  /// sample), and of those, the ones whose other transmitter was the majority of another signal
  /// then: both were tracked, so the separator could have known.
  std::uint32_t mixed_samples = 0;
  std::uint32_t mixed_samples_both_tracked = 0;
  std::uint32_t steps = 0;          ///< until the last victim was found (or the budget)
  double distance_m = 0.0;
  std::uint32_t signals = 0;        ///< signal ids the separation created
  /// Truth: the smallest carrier-offset difference between two of its transmitters (Hz). Under
  /// about 1 / on-time (5-14 Hz) two carriers fall in one frequency cell of the detector.
  double min_carrier_gap_hz = 0.0;
  /// Truth: of the pairs of transmitters whose carriers lie within one frequency cell
  /// (kCarrierCellHz), the longest time from the start that their pulses overlap at every pulse
  /// (s; pulses_overlap_for_s). All that time carrier and timing cannot tell them apart, only the
  /// field can.
  double lockstep_s = 0.0;
};

struct MultiBurialSummary {
  std::uint32_t victims = 0;
  double spread_m = 0.0;
  std::uint32_t trials = 0;
  std::uint64_t seed = 0;
  std::uint32_t all_found = 0;
  std::uint32_t ghosts = 0;
  std::uint32_t duplicates = 0;
  std::uint32_t founds = 0;
  std::uint32_t founds_outside_radius = 0;
  double worst_found_error_to_radius = 0.0;
  std::uint32_t located_signals = 0;
  std::uint32_t false_located = 0;
  std::uint32_t trials_with_false_located = 0;
  double worst_false_located_range_m = 0.0;
  Stats first_located_range_m;  ///< over every LOCATED signal of every trial
  std::uint32_t repeats_retired = 0;
  std::uint32_t repeats_wrong = 0;
  std::uint32_t repeats_suspected = 0;
  std::uint32_t trials_with_repeats = 0;  ///< trials in which some signal was suspected or retired
  std::uint32_t leaps = 0;
  std::uint32_t trials_with_leaps = 0;
  std::uint32_t implausible_rebuilds = 0;
  std::uint32_t trials_with_implausible_rebuilds = 0;
  std::uint32_t withdrawn_founds = 0;
  std::uint32_t trials_with_withdrawn_founds = 0;
  std::uint32_t line_resumptions = 0;
  std::uint32_t trials_with_line_resumptions = 0;
  std::uint32_t deferred_founds = 0;
  std::uint32_t trials_with_deferred_founds = 0;
  std::uint64_t wrong_attributions = 0;
  std::uint64_t mixed_samples = 0;
  std::uint64_t mixed_samples_both_tracked = 0;
  std::uint32_t trials_with_mixed_samples = 0;
  std::uint64_t unattributed_pulses = 0;
  Stats steps;                      ///< of the trials that found all
  Stats distance_m;
  double wall_s = 0.0;
  std::vector<MultiBurialTrial> per_trial;
};

/// What one trial did, for a step-by-step trace (sarloc-eval multi-burial --trace-trial N).
struct MultiBurialTraceVictim {
  Vec3 position = Vec3::Zero();  ///< truth, in the search frame (the rescuer starts at the origin)
  double moment_am2 = 0.0;
  TransmitterTiming timing;
};
/// One processed sample of one signal.
struct MultiBurialTraceSample {
  std::uint32_t signal_id = 0;
  std::uint8_t valid_axes = 0;
  std::optional<std::size_t> majority_victim;  ///< the transmitter most of its pulses came from
  std::optional<std::size_t> pulse_victim;     ///< the transmitter this sample's pulse came from
  /// Another transmitter whose pulse overlapped it on its carrier, and its energy over the
  /// dominant one's (HeardSample::mixed_with).
  std::optional<std::size_t> mixed_victim;
  double mixed_energy_ratio = 0.0;
  std::optional<double> truth_nis;             ///< HeardSample::truth_nis
  /// The sample's NIS against its signal's filter before the update (RescuerSearch::field_fit).
  std::optional<double> filter_nis;
  std::optional<VictimEstimate> estimate;      ///< as updated by this sample
  /// The estimate's 3-D error against its majority victim and its NEES (diagnostics).
  std::optional<double> error_m, nees;
  Vec3 estimate_at = Vec3::Zero();             ///< the estimate placed in the search frame
  std::optional<Guidance> guidance;            ///< when the sample is the target's
};
/// One step (1 s): the samples, then where the rescuer was sent.
struct MultiBurialTraceStep {
  std::uint32_t step = 0;
  std::vector<MultiBurialTraceSample> samples;
  Vec3 rescuer = Vec3::Zero();                 ///< before the step walked
  std::optional<std::uint32_t> target;
  std::optional<Guidance> guidance;            ///< what the rescuer walked (none: the primary line)
  std::uint32_t unattributed_pulses = 0;
  std::uint32_t found = 0;                     ///< victims found so far
};
struct MultiBurialTraceObserver {
  std::function<void(const std::vector<MultiBurialTraceVictim>&)> victims;
  std::function<void(const MultiBurialTraceStep&)> step;
};

MultiBurialTrial run_multi_burial_trial(const MultiBurialSetup& setup, std::uint32_t index,
                                        const MultiBurialTraceObserver* trace = nullptr);
MultiBurialSummary run_multi_burial(const MultiBurialSetup& setup, const std::function<void()>& on_trial_done = {},
                                    const std::function<bool()>& cancelled = {});

}  // namespace sarloc::avalanche
