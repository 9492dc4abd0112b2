#pragma once
// The receiver's pulse detector: finds the pulses in one listening window of complex baseband
// samples (pulse_train.hpp), each with its carrier offset, its on-interval and its complex
// amplitude per axis, also where pulses of several transmitters overlap.
//
// Successive detection and cancellation: the strongest tone-burst is found by a matched filter
// over carrier offset and start (a 70 ms window, the shortest on-time the standard allows); its
// on-interval and carrier offset are refined (the interval that maximises |sum|^2 / length,
// then the offset on a finer grid), it is subtracted, and the search repeats on the residual
// until nothing exceeds the detection threshold (chi-square, 6 dof, false alarms per window
// bounded). Finally all amplitudes are refitted jointly by least squares, which removes their
// mutual leakage, and each pulse gets its amplitude noise and variance inflation: how much the
// other pulses' overlap (same carrier, same time) degrades it. Overlapping pulses whose
// carriers are closer than about 1 / overlap cannot be told apart: their inflation is large.
// Before that final fit, a pulse that one tone leaves energy in is refitted as two bursts
// (pulse_pair_fit.hpp): two tones up to two_tone_span_hz apart (two transmitters a cell or two
// apart that start together are otherwise one burst at their mean carrier, whose field is
// neither's), or, with same_carrier_pairs, two pulses on one carrier with their own edges,
// searched over every interior edge (a pair in lockstep: otherwise one pulse whose field is a
// mixture). A pulse that another on its carrier outlasts and that no pair separates is flagged
// blended, and so is a same-carrier pair that the local pair refit does not separate.
//
//   std::vector<DetectedPulse> pulses = detect_pulses(window, PulseDetectorConfig{});
#include <vector>

#include "sarloc/core/avalanche/pulse_train.hpp"

namespace sarloc::avalanche {

struct PulseDetectorConfig {
  double search_band_hz = 100.0;       ///< carrier offsets searched: +- this (standard: +-80 Hz)
  double coarse_step_hz = 2.0;         ///< matched-filter grid (a 70 ms window resolves ~14 Hz)
  double fine_step_hz = 0.05;          ///< refinement grid around the coarse peak
  double min_on_time_s = 0.070;        ///< EN 300 718 minimum on-time: the matched window
  double max_on_time_s = 0.220;        ///< longest on-interval considered
  double min_fragment_s = 0.020;       ///< shortest piece of a pulse cut by the window's edges
  double false_alarms_per_window = 1e-3;
  /// A burst overlapping a pulse within a cell or so of its carrier and weaker than this
  /// fraction of its statistic (17 dB) is taken for that pulse's residual (its carrier or
  /// amplitude a fraction off). Further from the carrier the bound falls with the sidelobes of
  /// a burst as long as the overlap, (pi x cells)^-2, down to far_sidelobe_ratio, plus what an
  /// edge one sample off leaves inside the burst (1 / (pulse length x burst length) of the
  /// pulse's statistic per edge). Before, 17 dB held at any carrier distance: a deep victim's
  /// pulses 124 Hz from a shallow one's, 30 dB weaker and 76 dB above the noise, were never
  /// heard while the rescuer stood on the cluster (3 victims, seed 2, trial 8).
  double sidelobe_ratio = 0.02;
  /// The receiver's spurious-free dynamic range between carriers far apart (40 dB).
  double far_sidelobe_ratio = 1e-4;
  /// Within this many cells (sample rate / burst length) of any pulse's carrier only the flat
  /// sidelobe_ratio holds: two transmitters within a cell taken for one pulse leave a residual
  /// of a few per cent a cell or two away (3 victims, seed 2, trial 50: such bursts 1-2 cells
  /// from a pair 2 Hz apart, 0.5-2 % of it, fed wrong attributions and lost a victim).
  double near_carrier_cells = 3.0;
  /// A burst overlapping a pulse within one frequency cell and at least this fraction of its
  /// statistic (13 dB) is not a residual but another transmitter's pulse that cannot be resolved
  /// from it: the pulse is flagged blended (its field and edges are not its own).
  double blend_ratio = 0.05;
  std::uint32_t max_pulses = 8;
  double tracked_band_hz = 3.0;        ///< search band around a tracked carrier
  /// Two tones a cell or two apart that start together are found as one burst at their mean
  /// carrier (the 70 ms matched window cannot resolve them). A pulse that one tone leaves
  /// energy in is refitted as two tones, searched within +- this (Hz) of its carrier, and split
  /// when the pair captures more than one burst by the detection threshold plus a 30 dB model
  /// floor. 0: never split.
  double two_tone_span_hz = 20.0;
  /// The same screen also refits a pulse as two pulses on one carrier with different edges (a pair
  /// in lockstep), searched over every interior edge of the pulse and its same-cell mates.
  bool same_carrier_pairs = true;
};

struct DetectedPulse {
  double start_s = 0.0;
  double end_s = 0.0;
  double carrier_offset_hz = 0.0;
  Vec3c amplitude = Vec3c::Zero();   ///< per axis, referenced to t = 0 (IncomingPulse)
  Vec3 amplitude_noise = Vec3::Zero();  ///< 1 sigma of each real component of amplitude
  double statistic = 0.0;            ///< matched-filter statistic (chi-square 6 dof under noise)
  double variance_inflation = 1.0;   ///< joint fit variance / the pulse's own (1 = no overlap)
  bool blended = false;              ///< an unresolvable pulse overlapped it (blend_ratio)
  bool truncated_start = false;      ///< began before the window: the start is the window's
  bool truncated_end = false;        ///< still on at the window's end
  bool truncated() const { return truncated_start || truncated_end; }
};

/// `tracked_carriers`: carrier offsets of transmitters already tracked. Once the blind search
/// finds nothing more, each is searched again within +-tracked_band_hz only: far fewer tests,
/// so a lower threshold for the same false alarms (a tracking receiver hears further).
std::vector<DetectedPulse> detect_pulses(const BasebandWindow& window, const PulseDetectorConfig& config,
                                         const std::vector<double>& tracked_carriers = {});

}  // namespace sarloc::avalanche
