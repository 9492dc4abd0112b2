#pragma once
// Signal separation on the rescuer's device (issue 12): turns the pulses detected in each
// listening window (pulse_detector.hpp) into per-transmitter field samples with a signal id
// that stays the same for as long as the transmitter is tracked.
//
// A transmitter is tracked by what identifies it physically: its carrier offset (fixed per
// device, within +-80 Hz) and its pulse timing (period and on-time, learnt from its clean
// pulses). A pulse is attributed to a track when its carrier matches and its edges fall where
// the track's timing predicts (pulse_timing.hpp: a Kalman filter on phase and period whose gate
// widens with the periods predicted); confirmed tracks first. It is NOT attributed, and counted as such, when:
//   - the detector could not separate it from an overlapping pulse (variance inflation above
//     max_variance_inflation, or flagged blended: same carrier, same time), its polarisation is
//     elliptical (two transmitters' fields summed), or it lasts longer than its track's
//     on-time (two pulses merged into one);
//   - two tracks match it and the field-consistency hook (each track's filter) does not pick
//     one by a wide margin, or timing picked one and the hook says a carrier-mate's filter
//     explains its field by that margin;
//   - it matches nothing and cannot start a track (cut by the window's edges, or max_signals).
// A second transmitter on a tracked carrier (carriers within a frequency cell): a clean pulse
// clear of every carrier-mate's predicted pulse (its learnt on-time, widened by the gate), or
// heard at once with the mate's own pulse in the same window with neither edge shared (one
// transmitter cannot pulse twice at once), starts a *shadow* track, which publishes nothing until the evidence says it is another transmitter: it
// has its own period and shadow_confirm_pulses pulses, and a mate was heard on its own timing
// shadow_confirm_pulses times meanwhile. One transmitter cannot pulse on two interleaved trains,
// so one is never split into two signals (an earlier version confirmed such a track by its
// second pulse and, live, split a transmitter whose timing had drifted: docs/estimation/
// avalanche.md). A shadow whose mates all fall silent is the mate re-timed: it hands its timing
// over (kReacquired on the mate's id).
// Events: a track not heard for lost_after_s is declared lost; heard again, its next sample
// carries kReacquired (a lost track whose carrier alone matches a pulse that misses its timing
// is reanchored on that pulse: its timing estimate drifted while it was unheard; of several lost
// tracks on the carrier, the one that the rescuer's filters do not name a repeat of another:
// one transmitter split into two signals, FieldFit::repeat_of). Tracks that shared an unattributable pulse are merged; the next
// sample attributed to each carries kSeparated. Each sample's field is the major axis of its
// pulse's polarisation ellipse (principal_axis), sign unknown; axes below detect_snr are
// reported invalid. A pulse cut by the window's edge to less than the detector's matched window
// (min_on_time_s) gives no sample: an edge a sample off biases a 20 ms fragment's amplitude by
// 10 % and more, where a whole pulse's is biased by 1 %.
//
//   SignalSeparator separator(SeparatorConfig{});
//   SeparationReport r = separator.process(window);
//   for (const auto& s : r.samples) publish(s.signal_id, s.field, s.noise, s.valid_axes, s.event);
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/avalanche/field_fit.hpp"
#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/avalanche/pulse_detector.hpp"
#include "sarloc/core/avalanche/pulse_timing.hpp"
#include "sarloc/core/avalanche/quiet_span.hpp"
#include "sarloc/core/avalanche/transmitter_standard.hpp"

namespace sarloc::avalanche {

struct SeparatorConfig {
  PulseDetectorConfig detector;
  double detect_snr = 3.0;               ///< per-axis validity threshold (amplitude / noise)
  double calibration_relative = 0.0;     ///< added to each sample's noise, times |field|
  double carrier_match_hz = 2.0;         ///< a pulse's carrier matches a track within this, plus
  double carrier_match_weak_hz = 30.0;   ///< this / sqrt(statistic of the pulse or the track)
  double edge_sigma_s = 0.001;           ///< 1 sigma of a strong pulse's edge (half a sample), plus
  double edge_sigma_weak_s = 2.0;        ///< this / the pulse's statistic (weak edges are vague)
  double timing_gate_sigmas = 4.0;       ///< a pulse fits a track's timing within this many sigma
  /// A pulse longer than the track's on-time by more than the edges' gate and this is two
  /// pulses merged (the on-time learnt from weak pulses, whose edges the noise hides, runs short).
  double on_time_tolerance_s = 0.015;
  PulseTimingConfig timing;
  double max_variance_inflation = 2.0;   ///< overlap leaves a pulse this much noisier: unattributable
  /// A pulse whose polarisation ellipse is fatter (minor / major axis, beyond 3 sigma of noise)
  /// than one transmitter's can be is two transmitters' pulses summed. One is linear to within
  /// single_transmitter_ellipticity() of its strength: 0.6 (k r_max)^3, r_max the range of the
  /// strongest transmitter of the standard at that strength (0.1 at 50 m, 0.004 at 20 m); the
  /// device's three channels add channel_ellipticity (their phases matched to about 1.7 deg).
  double channel_ellipticity = 0.03;
  double wavenumber_rad_per_m = 2.0 * kPi * 457000.0 / 299792458.0;
  double moment_max_A_m2 = TransmitterStandard{}.moment_max();
  double lost_after_s = 5.0;             ///< declared lost after this silence
  double forget_after_s = 600.0;         ///< a track silent this long is dropped (its id retired)
  double log_likelihood_margin = 9.2;    ///< consistency hook must prefer a track by e^9.2 = 10^4
  /// A lost track is re-anchored on a pulse off its timing only if its filter (the consistency
  /// hook) explains the pulse's field: NIS inside chi2(this, one dof per valid axis).
  double reanchor_gate_probability = 0.9999;
  std::uint32_t max_signals = 8;
  /// A shadow track (a second transmitter on a tracked carrier) is promoted to a signal after
  /// this many pulses of its own, interleaved with as many of a mate's.
  std::uint32_t shadow_confirm_pulses = 3;
  /// Report a miss (SeparationReport::misses) when a confirmed track's whole pulse was due and
  /// nothing was detected on its carrier or over that pulse: negative information. Due in this
  /// window by its timing, or for every phase in its carrier's silence since last heard.
  bool report_misses = true;

  /// Throws ConfigError "separator.<key> = value: rule".
  void validate() const;
};

struct SeparatedSample {
  std::uint32_t signal_id = 0;
  Vec3 field = Vec3::Zero();        ///< receiver frame, sign unknown (A/m)
  Vec3 noise = Vec3::Zero();        ///< per-axis 1 sigma of field (A/m)
  std::uint8_t valid_axes = 0;
  SignalEvent event = SignalEvent::kNone;
  std::size_t pulse = 0;            ///< index into SeparationReport::pulses
};

enum class TrackChange : std::uint8_t { kNew, kLost, kMerged, kReacquired, kSeparated, kForgotten };
const char* to_string(TrackChange change);

struct TrackEvent {
  std::uint32_t signal_id = 0;
  TrackChange change = TrackChange::kNew;
  double time_s = 0.0;
};

struct SeparationReport {
  std::vector<DetectedPulse> pulses;                   ///< everything the detector found
  std::vector<std::optional<std::uint32_t>> attributed;///< per pulse: its signal, or none
  std::vector<SeparatedSample> samples;                ///< at most one per signal: its best pulse
  /// Signals whose whole pulse was due (in the window, for every timing within its gate or for
  /// any phase when the period is shorter than the window less the on-time; or, in the silence
  /// of their carrier since last heard, for every phase: QuietSpan), with nothing detected on
  /// their carrier or over that pulse: field 0, valid_axes 0, noise the 70 ms pulse floor of
  /// each axis. Never a signal that has a sample in this window.
  std::vector<SeparatedSample> misses;
  std::uint32_t unattributed = 0;
  std::vector<TrackEvent> events;
};

/// How well a field sample fits the filter of a signal (nullopt: no filter yet).
using FieldConsistency =
    std::function<std::optional<FieldFit>(std::uint32_t signal_id, const Vec3& field, const Vec3& noise, std::uint8_t axes)>;

class SignalSeparator {
 public:
  explicit SignalSeparator(SeparatorConfig config = {});
  void set_consistency(FieldConsistency consistency) { consistency_ = std::move(consistency); }

  SeparationReport process(const BasebandWindow& window);

  /// Tracked signals right now (lost ones included until forgotten).
  std::size_t tracks() const { return tracks_.size(); }
  /// Carrier offset of a tracked signal (Hz), nullopt if unknown.
  std::optional<double> carrier_of(std::uint32_t signal_id) const;
  /// What the separation has measured of a tracked signal's transmitter: its carrier (the
  /// weighted mean, sigma the spread of its pulses' carriers over sqrt(pulses), from two pulses)
  /// and its period (once its timing knows it; never for a track reanchored onto a period that
  /// disagrees with its own before: it followed another transmitter's pulses). Against this
  /// receiver's oscillator: the caller adds that tolerance (BeaconReceiver). nullopt for an
  /// unknown signal.
  std::optional<responder::TransmitterSignature> signature_of(std::uint32_t signal_id) const;
  /// Overlapping pulses on one carrier: noisier than max_variance_inflation allows, blended, or
  /// elliptical. No track can take it (the others are let through to the tracks).
  bool unseparable(const DetectedPulse& p) const;

 private:
  struct Track {
    std::uint32_t id = 0;
    double carrier_hz = 0.0;
    double carrier_weight = 0.0;       ///< sum of the statistics averaged into carrier_hz
    // Its pulses' carriers, unweighted (Welford), for signature_of's sigma.
    std::uint32_t carrier_pulses = 0;
    double carrier_pulse_mean = 0.0;
    double carrier_pulse_m2 = 0.0;
    /// Its period and sigma when last reanchored, until its timing says whose it follows now.
    std::optional<std::pair<double, double>> period_before_reanchor;
    /// Its period after a reanchor disagreed with the one before: it has followed two
    /// transmitters' timings, and its signature states no period (signature_of).
    bool retimed = false;
    std::optional<double> on_time_s;   ///< from clean (untruncated) pulses, weighted by statistic
    double on_time_weight = 0.0;
    PulseTiming timing;                ///< confirmed once it knows the period
    double last_heard_s = 0.0;
    bool lost = false;
    bool merged = false;
    SignalEvent pending = SignalEvent::kNew;
    std::uint32_t heard = 0;           ///< pulses attributed
    /// A shadow: started on a tracked carrier, off every mate's timing; per mate at its start,
    /// (id, mate's heard then). Publishes nothing until promoted (interleaved()).
    bool shadow = false;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> mates_at_start;
    QuietSpan quiet;                   ///< its carrier's silence since last heard (misses)
  };

  double edge_sigma(const DetectedPulse& p) const;
  /// Start of the pulse and its 1 sigma; a pulse cut at the window's start is dated by its end.
  std::optional<std::pair<double, double>> start_of(const Track& t, const DetectedPulse& p) const;
  bool timing_fits(const Track& t, const DetectedPulse& p) const;
  /// The pulse's carrier matches the track's (a weak one's within a wider tolerance).
  bool on_carrier(const Track& t, const DetectedPulse& p) const;
  /// Where a whole pulse of t lies in [w0, w1) for every timing within its gate (the whole
  /// window when the period is short enough for any phase), nullopt if none is sure to.
  std::optional<std::pair<double, double>> whole_pulse_due(const Track& t, double w0, double w1) const;
  bool elliptical(const DetectedPulse& p) const;
  /// The mate knows its timing, was heard within 1.5 periods and predicts its pulse clear of
  /// this one (its learnt on-time, widened by its gate and on_time_tolerance_s).
  bool clear_of_timing(const Track& mate, const DetectedPulse& p) const;
  /// A whole pulse attributed to the mate in this window overlaps this one in time, and neither
  /// edge is shared: two transmitters pulsing at once.
  bool heard_at_once(const Track& mate, const DetectedPulse& p, const SeparationReport& r) const;
  /// Every carrier-mate is either clear_of_timing or heard_at_once: not its pulse.
  bool another_transmitter(const std::vector<Track*>& mates, const DetectedPulse& p, const SeparationReport& r) const;
  /// The lost track among the carrier matches (the one, or of several the one that is no repeat
  /// of another: original_of_repeats) whose every other match says the pulse is not its own
  /// (another_transmitter), and whose filter explains the pulse's field (explains): it lost its
  /// timing, and this pulse re-anchors it.
  Track* lost_owner(const std::vector<Track*>& matches, const DetectedPulse& p, const SeparationReport& r) const;
  /// Of several tracks that carrier and timing fit, the one whose filter explains the pulse
  /// better than every other's by log_likelihood_margin; nullptr: the filters cannot tell.
  Track* chosen_by_filters(const std::vector<Track*>& candidates, const DetectedPulse& p) const;
  /// Of several lost tracks on the pulse's carrier, the one whose filter is no suspected repeat
  /// of another's (FieldFit::repeat_of), if exactly one is; else nullptr.
  Track* original_of_repeats(const std::vector<Track*>& lost, const DetectedPulse& p) const;
  /// The track's filter (consistency hook) explains the pulse's field within
  /// reanchor_gate_probability; true when there is no hook or no filter yet to ask.
  bool explains(const Track& t, const DetectedPulse& p) const;
  /// A new track for p; a shadow of its carrier-mates if it has any.
  Track& start_track(const DetectedPulse& p, const std::vector<Track*>& carrier_matches);
  /// A shadow heard shadow_confirm_pulses times on its own period while a mate was too.
  bool interleaved(const Track& shadow) const;
  const Track* find(std::uint32_t id) const;
  Track* find(std::uint32_t id);
  /// End of a window: promote the shadows that proved themselves, hand over those whose mates
  /// all went silent, drop those unheard.
  void settle_shadows(SeparationReport& r, double window_end);
  /// Timing gave the pulse to `chosen`, but the consistency hook says another track on its
  /// carrier explains its field by more than log_likelihood_margin: not attributed.
  bool better_fit_elsewhere(const Track& chosen, const std::vector<Track*>& mates, const DetectedPulse& p,
                            std::size_t index) const;
  void learn(Track& t, const DetectedPulse& p);
  SeparatedSample sample_of(const DetectedPulse& p, std::uint32_t id, std::size_t index) const;

  SeparatorConfig config_;
  std::vector<Track> tracks_;
  std::uint32_t next_id_ = 1;
  FieldConsistency consistency_;
  double reanchor_gate_[4] = {};  ///< chi-square quantile per number of valid axes
};

}  // namespace sarloc::avalanche
