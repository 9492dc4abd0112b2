#pragma once
// Everything one rescuer's search needs, for every signal its receiver separates: one
// SogFilter and SearchController per signal (nothing single-victim), the odometry fanned out
// to all of them, a gate that refuses bad samples before they touch any filter, and the choice
// of which signal to guide the rescuer to.
//
// Used identically by the core daemon (one RescuerSearch per rescuer it serves) and by the
// rescuer's device when the daemon is unreachable, so both give the same guidance.
//
//   RescuerSearch search("r1", RescuerSearchConfig{});
//   if (auto rejected = search.add_odometry(odo)) log(rejected->detail);
//   auto outcome = search.process(measurement);
//   if (auto* update = std::get_if<SearchUpdate>(&outcome)) publish(update->estimate, update->guidance);
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <variant>

#include "sarloc/core/avalanche/search_controller.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/avalanche/responder_types.hpp"

namespace sarloc::avalanche {

struct RescuerSearchConfig {
  SogConfig sog;
  SearchConfig search;
  std::size_t summary_components = 5;  ///< components in each VictimEstimate (IDL bound: 8)
  std::uint32_t max_signals = 8;       ///< receivers separate a handful of signals; more is bad input
  double max_step_m = 10.0;            ///< one odometry sample moving further is absurd (m)
  double max_rotation_rad = 3.2;       ///< |rpy| of one odometry sample beyond this is absurd
  /// Motion assumed when odometry is missing (add_unknown_motion): per-axis sigma of the
  /// displacement per second (a rescuer walks ~1 m/s in any direction) and of the yaw change.
  double unknown_motion_speed_m_per_s = 1.0;
  double unknown_motion_turn_rad_per_s = 0.5;
  /// A field sample is refused when the odometry already received reaches more than this
  /// beyond its stamp: its filter would otherwise apply motion made after the sample was taken.
  double measurement_lag_tolerance_s = 0.5;
  /// The target stays the target until found, unless it has been silent this long while
  /// another unfound signal is heard: then the strongest one heard is searched (a searcher
  /// follows the signal that can be heard, not one lost at the edge of range).
  double target_silence_s = 10.0;
  /// One transmitter split into two signals (same_transmitter.hpp): a signal whose position and
  /// moment are inside chi2_6(this) of another signal's that stands as a victim here (found, or
  /// kLocated) is a suspected repeat of it and confirms nothing; found there, it is a confirmed
  /// repeat and the search moves on. Measured at FOUND (docs/estimation/avalanche.md): repeats
  /// 2.0 and 3.8, two transmitters 44.7 and more, but 13-14 for one found hundreds of steps
  /// earlier, whose position the odometry had blurred to metres (a victim lost: "Left").
  double same_transmitter_gate_probability = 0.999;
  /// A repeat is confirmed only while both moments are known to this fraction of their
  /// magnitude (1 sigma); otherwise the signal stays suspected: the device cannot tell.
  double same_transmitter_moment_spread = 0.25;
  /// Found witness (multiple burials): before a FOUND is given, a second filter is built from
  /// this many seconds of the signal's latest samples only, replayed with the odometry. While it
  /// cannot nearly locate the victim (found_witness_radius_factor) the FOUND waits; when it
  /// locates it elsewhere (d^2 with summed covariances beyond
  /// chi2_3(found_witness_gate_probability)) the FOUND is withdrawn and the signal's filter takes
  /// the witness's hypotheses beside its own. A filter fed another transmitter's pulses earlier
  /// (a carrier-mate in lockstep, a sum the separation let through) keeps what it learnt of that
  /// one's moment and fits the right transmitter's clean pulses from the wrong place with a small
  /// radius (avalanche.md, "Found witness"). 0 = off.
  double found_witness_window_s = 30.0;
  double found_witness_gate_probability = 0.999;
  /// ... and the FOUND waits while the witness's 95 % radius exceeds this many times the radius
  /// the FOUND claims: the located radius, or the filter's own when larger (a FOUND the adaptive
  /// end gives). The latest samples alone must nearly locate the victim too.
  double found_witness_radius_factor = 2.0;

  /// Throws ConfigError naming the key ("rescuer_search.max_signals = 0: must be in [1, 64]").
  void validate() const;
};

struct SearchUpdate {
  /// Of the measured signal, status refined by assess(). None for a pulse not heard (valid_axes
  /// 0) of a signal without a filter, or found here: nothing changed.
  std::optional<VictimEstimate> estimate;
  std::optional<Guidance> guidance; ///< present when the measured signal is the target
};

/// A converged target silent while the rescuer is this near it (or within its 95 % radius) has
/// been switched off (RescuerSearch::coast).
inline constexpr double kSilencedReachM = 2.0;

/// Longest gap add_unknown_motion() stands in for.
inline constexpr TimestampNs kMaxUnknownMotionNs = 10'000'000'000;
/// Longer gaps restart the unfound filters, up to this; beyond it the stamp is taken for bad input.
inline constexpr TimestampNs kMaxFrameGapNs = 600'000'000'000;

class RescuerSearch {
 public:
  RescuerSearch(std::string rescuer_id, RescuerSearchConfig config);

  /// Odometry for every signal's filter. Returns the rejection, if refused (state untouched).
  /// A gap of over 10 s between the previous step's end and this one's start (steps lost for
  /// good) restarts the unfound signals' filters; a gap over 600 s is refused (bad stamp).
  std::optional<Rejection> add_odometry(const Odometry& odometry);

  /// The odometry over [from, until] did not arrive in time (late or lost on the network):
  /// stand in a zero displacement with the covariance of unknown_motion_* over that interval,
  /// so the next update is not made as if the rescuer had stood still. Odometry samples ending
  /// at or before `until` are refused afterwards (kSuperseded): applying them too would count
  /// the motion twice. Assumes odometry intervals end at measurement stamps (as the rescuer
  /// node sends them); a sample straddling `until` is refused as kStampBackwards. Returns false
  /// (nothing done) when until <= the last odometry end or the gap exceeds 10 s (not a late
  /// step: a stamp far in the future must not shut the rescuer's odometry out).
  bool add_unknown_motion(TimestampNs from, TimestampNs until);

  /// One field sample of one signal. Refused samples leave every filter untouched. Once this
  /// rescuer has found the signal's victim, its filter takes no more measurement updates: the
  /// update carries the estimate of the moment it was found, unchanged (its stamp, its frame:
  /// paired with that moment's GNSS fix it is the best position for incident command, and
  /// republishing it answers the epoch), while estimate(signal) is that one moved into the
  /// current frame by the odometry since (for the display). A pulse due and not heard
  /// (valid_axes 0) updates the signal's filter (SogFilter::process) but never raises its status,
  /// and, for the target, carries coast() guidance.
  std::variant<SearchUpdate, Rejection> process(const FieldMeasurement& measurement);

  /// Guidance to the target from its filter moved by the odometry since it was last heard,
  /// for an epoch in which the target's signal was not received (out of range, lost
  /// sample): the rescuer keeps heading for it instead of stopping. nullopt without a target.
  std::optional<Guidance> coast(TimestampNs stamp);

  /// The signal is a victim already found (by this rescuer or reported by incident command):
  /// stop guiding to it.
  void mark_done(std::uint32_t signal_id);
  /// These signals' victims are pursued by other rescuers (incident command's search plan,
  /// incident/signal_pursuit.hpp): not guided to while in the set; the filters keep listening.
  /// Replaces the previous set (a hand-over lifted gives the signal back). The hand-over lapses
  /// once a sample is stamped after `until` (the plan's stamp plus a margin): a plan from an
  /// incident command that fell silent hides no victim for long.
  void leave_to_others(std::set<std::uint32_t> signal_ids, TimestampNs until);

  /// Signal the rescuer is guided to (nullopt before any measurement or when all are done).
  std::optional<std::uint32_t> target_signal() const { return target_; }
  const std::string& rescuer_id() const { return rescuer_id_; }
  std::size_t signal_count() const { return signals_.size(); }
  /// Times the unfound filters restarted after a gap in the motion too long to stand in for.
  std::size_t restarts() const { return restarts_; }
  /// Filters rebuilt because their estimate left its own earlier posterior (SogConfig leap test).
  std::size_t leaps() const { return leaps_; }
  /// Filters rebuilt after converging on no plausible transmitter (SogConfig::implausible_rebuild_steps).
  std::size_t implausible_rebuilds() const { return implausible_rebuilds_; }
  /// Times a signal's search walked the primary line again, lost while wide (SearchConfig::lost_signal_steps).
  std::size_t line_resumptions() const;
  /// Latest estimate of a signal (nullopt if never measured).
  std::optional<VictimEstimate> estimate(std::uint32_t signal_id) const;
  /// Signals retired as confirmed repeats of another (the same transmitter, found twice).
  std::size_t confirmed_repeats() const { return confirmed_repeats_; }
  /// FOUNDs withdrawn because the found witness converged elsewhere.
  std::size_t withdrawn_founds() const { return withdrawn_founds_; }
  /// FOUND claims that waited because the found witness could not yet locate the victim.
  std::size_t deferred_founds() const { return deferred_founds_; }
  /// Targets left because their transmitter fell silent while the rescuer stood on them.
  std::size_t silenced_targets() const { return silenced_targets_; }
  /// How well a field sample would fit a signal's filter (SogFilter::predictive_fit): the
  /// receiver's separation (SignalSeparator::set_consistency) asks it. nullopt for a signal
  /// without a filter yet.
  std::optional<FieldFit> field_fit(std::uint32_t signal_id, const Vec3& field, const Vec3& noise,
                                    std::uint8_t axes) const;

 private:
  /// One input of the filters: odometry, unknown motion stood in for it, a field sample.
  using RecentInput = std::variant<Odometry, DispCov, FieldMeasurement>;
  struct SignalState {
    SogFilter filter;
    SearchController controller;
    std::uint64_t last_sequence = 0;
    TimestampNs last_stamp = 0;        ///< of its last sample, heard or not (ordering)
    TimestampNs last_heard_stamp = 0;  ///< of its last pulse heard (silence)
    double last_field_norm = 0.0;
    std::optional<VictimEstimate> estimate;
    bool done = false;        ///< not to be guided to: found here or elsewhere
    /// Set when this rescuer stood over it (GuidanceMode::kFound): the estimate of that moment.
    std::optional<VictimEstimate> found;
    /// Set when stood over as a confirmed repeat of another signal: the estimate of that moment
    /// (status kConverged), kept and republished like a found one.
    std::optional<VictimEstimate> retired = std::nullopt;
    SignalEvent last_event = SignalEvent::kNone;  ///< the separation's last word on this signal
    TimestampNs last_event_stamp = 0;
    responder::RepeatState repeat = responder::RepeatState::kNone;  ///< of another signal here
    std::uint32_t repeat_of = 0;
    responder::TransmitterSignature transmitter = {};  ///< the separation's latest word on it
    /// Stood over (converged, within reach) with the device hearing nothing at all: its
    /// transmitter is off. Not guided to until a pulse of it is heard again.
    bool silenced = false;
  };

  std::optional<Rejection> gate(const FieldMeasurement& m) const;
  std::variant<SearchUpdate, Rejection> process_miss(const FieldMeasurement& m);
  /// The sample into the signal's filter; on success the signal's and the search's clocks advance.
  std::optional<Rejection> update_filter(SignalState& s, const FieldMeasurement& m);
  /// e carrying the separation's last word on the signal and its repeat state (a repeat
  /// confirms nothing: its status is capped at kConverged).
  static VictimEstimate with_signal_state(const SignalState& s, VictimEstimate e);
  /// The same-transmitter test of signal `id` (status `status`, found just now or not) against
  /// the other signals standing as victims here; sets its repeat state: confirmed when found
  /// where another signal's victim was found and both moments are known, else suspected.
  void test_repeat(std::uint32_t id, SignalState& s, EstimatorStatus status, bool found_now);
  void choose_target();
  /// Neither done nor handed over to another rescuer (leave_to_others, not lapsed).
  bool may_guide_to(std::uint32_t signal_id, const SignalState& s) const;
  void restart_unfound_filters();
  /// The found witness of signal `id` (see found_witness_window_s): a filter replayed from the
  /// inputs logged since `since`; nullopt when the replay refused an input.
  std::optional<SogFilter> found_witness(std::uint32_t id, TimestampNs since) const;
  /// Whether the witness stands by s's FOUND; if not, s continues from the witness.
  bool witnessed(std::uint32_t id, SignalState& s, TimestampNs now);
  void log_input(TimestampNs stamp, RecentInput input);

  std::string rescuer_id_;
  RescuerSearchConfig config_;
  std::map<std::uint32_t, SignalState> signals_;
  std::set<std::uint32_t> done_;
  std::set<std::uint32_t> left_to_others_;
  TimestampNs left_until_ = 0;
  std::optional<std::uint32_t> target_;
  TimestampNs newest_stamp_ = 0;  ///< of any signal's last measurement
  /// The primary search's line, as a bearing from the rescuer's heading now: 0 when the device
  /// first heard a pulse (he was walking it), turned by every odometry sample's yaw since, and
  /// given to each signal's controller (SearchController::primary_line_at). Unknown again after a
  /// gap that restarts the filters (the turns made in it are lost).
  std::optional<double> line_bearing_;
  /// Coasted epochs since the device last heard a pulse of any signal (SearchConfig::lost_signal_steps).
  std::uint32_t quiet_epochs_ = 0;
  std::optional<std::uint64_t> last_odometry_sequence_;
  TimestampNs last_odometry_end_ = 0;
  TimestampNs superseded_until_ = 0;  ///< end of the last unknown-motion stand-in
  std::size_t restarts_ = 0;
  std::size_t leaps_ = 0;
  std::size_t implausible_rebuilds_ = 0;
  std::size_t confirmed_repeats_ = 0;
  std::size_t withdrawn_founds_ = 0;
  std::size_t deferred_founds_ = 0;
  std::size_t silenced_targets_ = 0;
  double same_transmitter_gate_ = 0.0;  ///< chi2_6(same_transmitter_gate_probability)
  double witness_gate_ = 0.0;           ///< chi2_3(found_witness_gate_probability)
  /// What the filters were given, in order, over the last found_witness_window_s: replayed
  /// into a found witness.
  std::deque<std::pair<TimestampNs, RecentInput>> recent_;
};

}  // namespace sarloc::avalanche
