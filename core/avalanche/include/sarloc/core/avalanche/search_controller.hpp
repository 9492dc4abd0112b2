#pragma once
// Search control for one signal (seed 000, section III-C), and the uniform "located" / "found"
// criterion used by the evaluation.
//
// Modes (GuidanceMode):
//   kOpening         the opening phase (seed 000's flux-line phase). Heading by
//                    opening_heading: kLookahead (default) walks the straight line whose next
//                    steps are expected to leave the shortest way, counting the detour that
//                    the remaining bearing ambiguity costs (lookahead_heading.hpp);
//                    kPosteriorBearing walks toward the most probable bearing of the mixture
//                    (BearingDensity) and keeps its heading until another bearing is
//                    bearing_switch_ratio times as probable; kFluxLine walks along the
//                    horizontal projection of the measured field line, SNR-weighted and low-pass
//                    filtered (flux_smoothing), its sense kept continuous, the first one towards
//                    the mixture mean. Measured (docs/estimation/avalanche.md, "Opening
//                    heading"): posterior bearing saves 0.7-0.9 steps a trial over the flux
//                    line, the lookahead another 0.3;
//   kApproach        once the receiver is far enough from the mixture mean in Mahalanobis terms
//                    (horizontal d^2 = p^T P^-1 p > approach_mahalanobis^2), walk to the mean;
//   kFineSearch      horizontal distance < fine_search_radius_m: steps of min(step, distance);
//   kFound           located AND the rescuer stands within found_distance_m of the estimate,
//                    or the adaptive end below; either way on found_confirmations guided samples
//                    in a row (after the first, probes found_distance_m to alternate sides of
//                    the estimate, counted while it stays located and each was taken between
//                    half and twice that from it; between samples, coast() waits on the probe
//                    point, for three epochs at most).
// Adaptive end (docs/estimation/avalanche.md, "The search always ends"): with noisy sensors the
// 95 % radius can level off above the located radius while the estimate is already as good as
// the data make it, and the rescuer would probe on the spot forever. In fine search, once the
// 95 % radius has not shrunk by stall_min_improvement (relative to its best) for
// stall_window_steps steps (StallDetector) and the estimate is converged
// (sog.converged_radius_m) and below the receiver, the rescuer walks a probe pattern
// (probe_pattern.hpp): every point of the horizontal 95 % region of the estimate lies within
// found_distance_m of one of its points, each visited in turn (the guidance stays
// kFineSearch). At its end the search is kFound with the estimate of that moment, stated with
// its own 95 % radius. The pattern, complete or not, is dropped (and the stall watch restarts)
// if the 95 % radius grows by half over the one it was laid out for. The fixed criterion keeps priority:
// reached at any step, it ends the search as before, so runs that reach it are unchanged.
// Criteria (applied identically in every trial):
//   located: 95 % radius of the mixture position, sqrt(chi2_3(0.95) lambda_max(P_p)),
//            <= min(located_radius_max_m, max(located_radius_m, located_radius_per_range * |p_mean|)) (eq. (18)
//            includes the spread between modes, so a multimodal mixture is never "located");
//   found:   located and horizontal |p_mean| <= found_distance_m (G_k is rescuer-centred);
//   neither while the estimate is not below the receiver (z + 2 sigma_z < 0): a victim is
//   buried, so an estimate above is a filter's mirror solution (H(r) = H(-r)); nor without
//   enough samples, recent and newest innovations within their gates and a moment the
//   transmitter standard allows (ConfirmationEvidence).
//
//   SearchController ctl(SearchConfig{});
//   Guidance g = ctl.guide(filter, measurement);   // after filter.process(measurement)
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/avalanche/lookahead_heading.hpp"
#include "sarloc/core/avalanche/responder_types.hpp"
#include "sarloc/core/avalanche/stall_detector.hpp"
#include "sarloc/core/avalanche/transmitter_filter.hpp"

namespace sarloc::avalanche {

/// How the opening phase picks its heading (see the mode list above).
enum class OpeningHeading { kPosteriorBearing, kFluxLine, kLookahead };
/// "lookahead" / "posterior_bearing" / "flux_line"; parse throws ConfigError naming search.opening_heading.
const char* to_string(OpeningHeading h);
OpeningHeading parse_opening_heading(const std::string& text);

struct SearchConfig {
  double step_length_m = 1.0;          ///< nominal step (seed 000: 1 m/s, 1 measurement/s)
  double approach_mahalanobis = 1.0;   ///< leave the opening phase beyond this distance
  /// ... and only once the mixture's 95 % horizontal radius has shrunk to this fraction of
  /// its initial value (a ring still uniform at the noise floor has a wandering mean).
  double approach_radius_fraction = 1.0;
  double fine_search_radius_m = 2.0;   ///< below this horizontal distance: fine search
  double located_radius_m = 0.4;       ///< 95 % 3-D radius for "located" (near range)
  /// ... or this fraction of the antenna-to-victim distance, whichever is larger: precision
  /// scales with range, so deep burials are located at a proportionally larger radius.
  double located_radius_per_range = 0.10;
  /// ... but never more than this: LOCATED means "precise enough to walk onto", the radius under
  /// which incident command calls a fused victim located (fusion.located_radius_m). Seen live: a
  /// device LOCATED a signal 39 m away with a 3.9 m radius, 29 m from any victim, and the picture
  /// confirmed it (docs/estimation/incident-fusion.md, "Withdrawal").
  double located_radius_max_m = 1.0;
  double found_distance_m = 0.5;       ///< horizontal distance to the estimate for "found"
  /// kLocated and kFound need at least this many samples of the signal's current mixture
  /// (TransmitterFilter::mixture_samples, counted again after a rebuild): a filter started next to a
  /// cluster of victims converged in 3-4 near-field samples on a place where no one was buried
  /// (multiple burials, a ghost). Single searches take 40+ samples.
  double confirm_min_samples = 10.0;
  /// ... and their filter's recent innovations within this fraction of its divergence gate
  /// (InnovationRecord::recent_ratio): a filter whose last samples do not fit it has taken
  /// another transmitter's pulses, or lost its own. 4 victims within 5 m, 100 trials: 6 of the 8
  /// FOUNDs near no victim were above 1, against 5 of 388 right ones.
  double confirm_max_innovation_ratio = 1.0;
  /// ... and the same ratio over this many samples of the mixture (SogFilter::
  /// innovation_ratio_over): a converged filter that lost its transmitter is kept (its
  /// innovation excess is taken for near-field linearisation), and the six-sample window forgets
  /// the excess while the filter creeps off. Seen: NIS 13-47 a sample for 30 samples, then 0.4-15
  /// for six, and a FOUND 3 m from the victim with a 0.3 m radius (4 victims, seed 1, trial 6).
  std::uint32_t confirm_innovation_window = 18;
  /// ... and the newest sample's smallest NIS within this (chi2_3(0.999) = 16.27): a FOUND was
  /// seen declared on the very sample that moved a near-field estimate 1.7 m off (NIS 24).
  double confirm_max_last_nis = 16.27;
  /// ... and the samples taken while the estimate was already within its located radius (the
  /// probe samples, those it claimed to predict closely) fitting it: the NIS sum of the latest
  /// confirm_probe_window of them within chi2(their valid axes, confirm_probe_gate_probability)
  /// (InnovationRecord::within). The six- and 18-sample windows are diluted by the far
  /// samples of a wide ring. Seen: a filter fed another transmitter's pulses converged 0.9 m off
  /// with a 0.18 m radius, its probe samples' NIS 8 on average (3 axes), and was FOUND (4
  /// victims, seed 17 trial 45; tail 1e-5, against none of 1190 right FOUNDs below 1e-3).
  std::uint32_t confirm_probe_window = 14;
  double confirm_probe_gate_probability = 0.999;
  /// ... and the filter's latest samples alone allowing the victim no farther from the estimate
  /// than this many times its located radius (TransmitterFilter::window_reaches): a filter that
  /// collapsed early on a wrong place near a deep victim states a radius its samples do not hold
  /// (4 victims seed 10 trial 67: FOUND 1.18 m off with a 0.29 m radius, its last 11 samples
  /// allowing 1.22 m). 0 = off.
  double confirm_window_reach_factor = 2.0;
  /// kFound needs this many consecutive samples that each say "found" (the rescuer probes
  /// sideways meanwhile, as a searcher brackets the minimum): one near-field update can move
  /// an estimate a metre with a small covariance, and the next samples from beside it tell.
  std::uint32_t found_confirmations = 3;
  /// The confirming samples are taken this fraction of the victim's depth below the antenna to
  /// either side of the estimate, or found_distance_m if that is further: the same angle seen
  /// from the victim whatever its depth. 0.5 m beside a victim 3.9 m below the antenna changes
  /// the field too little to tell a place 1 m off (seen: a FOUND 0.99 m off with a 0.44 m radius,
  /// 4 victims seed 2 trial 12). 0.35: about 19 degrees seen from the victim. 0 = always found_distance_m.
  double confirm_probe_per_depth = 0.35;
  /// Epochs a rescuer confirming a FOUND or walking a probe pattern waits on a probe point for
  /// the signal's next sample, at most: as long as its recent gaps (at least 3), up to this.
  /// Seen: a victim heard every 6-8 epochs under a carrier-mate's pulses, the rescuer leaving
  /// each probe point after 3, never confirmed in 750 s (4 victims, seed 1, trial 48); and
  /// with 10, victims located 0.03-0.1 m off, heard once in 10-20 epochs under a neighbour 5-13
  /// Hz away, never confirmed in 800 (seed 10 trial 9, seed 13 trial 96). Not for ever: a
  /// signal not heard there sends the rescuer back to the estimate.
  std::uint32_t confirm_max_waits = 30;
  double probe_step_m = 0.5;           ///< sideways step when on top but not yet located
  double flux_smoothing = 0.7;         ///< memory of the SNR-weighted flux-line direction
  double flux_snr_cap = 10.0;          ///< SNR above which a direction gets no extra weight
  /// A measured flux direction turns the rescuer only by its SNR^2 in excess of this value
  /// (per horizontal axis; flux_line opening only). Pure noise has E[SNR^2] = 1, so a reading
  /// at the noise floor leaves him walking straight (the baseline that makes |z|
  /// informative). A stricter 3.0 (chi2_2(0.95)/2) measured worse (docs/estimation/avalanche.md).
  double flux_detection_snr2 = 1.0;
  OpeningHeading opening_heading = OpeningHeading::kLookahead;
  /// Up to this many samples of the opening search keep the rescuer on the primary search's
  /// line, until the posterior has narrowed enough to leave the opening search: a real
  /// receiver first hears a pulse now and then at the edge of range, and a turn on such a
  /// ring walks out of range half of the time (measured: 10 of 40 trials lost).
  std::uint32_t opening_line_samples = 60;
  /// Farther than this from where the signal was last heard without hearing it again: head
  /// back there (what a searcher who lost the signal does). Walking on, straight or for a
  /// mixture still wide, can leave the range for good (1-2 trials in 100 walked off at 40-50 m);
  /// a hypothesis this close would have been heard on the way.
  double coast_return_m = 10.0;
  /// Unheard this many epochs in a row while the estimate has not converged (the mixture still
  /// wider than sog.converged_radius_m): the rescuer is out of the signal, or its geometry told
  /// nothing. The search re-plans: back to the primary search's line, swept from where he is
  /// until the signal is heard again, where the opening search starts over (a primary strip
  /// passes within its half width of every victim, where the ring narrows).
  /// Walking to the wide mixture's mean and back to where the signal was last heard, he shuttled
  /// at the edge of range for the rest of the search (seed 12, trial 0). It waits for the
  /// device to hear nothing at all as long (coast's device_quiet_epochs): a signal masked by
  /// found neighbours' pulses, next to a cluster, is not out of range, and sweeping away from
  /// the cluster cost multiple burials their misses. 0 = off (docs/estimation/avalanche.md,
  /// "Every search ends").
  std::uint32_t lost_signal_steps = 15;
  /// The re-planned sweep stays within this distance of where the signal was last heard: past
  /// it, with that place behind him, the rescuer turns round on the line. The victim was heard
  /// from there, so it lies within the receiver's range of it (40-70 m for the realistic
  /// receiver); an unbounded walk "until heard" took a live rescuer 299 m away (issue 58).
  double lost_line_half_length_m = 50.0;
  /// Angular width (1 sigma) of the kernel smoothing the posterior bearing density: wide
  /// enough that an arc of the ring counts as one direction, narrow enough to tell arcs apart.
  double bearing_kernel_deg = 35.0;
  /// Keep the current opening heading until the most probable bearing carries this many times
  /// its probability: a near-uniform ring would otherwise turn the rescuer every step, and
  /// walking straight is what makes the field magnitude informative.
  double bearing_switch_ratio = 2.0;
  /// opening_heading = lookahead: the information-aware planner (lookahead_heading.hpp).
  LookaheadConfig lookahead;
  /// Adaptive end (see above): fine-search steps without the 95 % radius shrinking by
  /// stall_min_improvement before the probe pattern starts. 0 = off (fixed radius only).
  int stall_window_steps = 10;
  /// Relative shrink of the 95 % radius below its best that counts as progress.
  double stall_min_improvement = 0.05;

  /// Throws ConfigError "search.<key> = value: rule".
  void validate() const;
};

/// What a filter says about whether its estimate may be confirmed (LOCATED, FOUND).
struct ConfirmationEvidence {
  std::uint64_t samples = 0;      ///< TransmitterFilter::mixture_samples
  double innovation_ratio = 0.0;  ///< InnovationRecord::recent_ratio
  double last_nis = 0.0;          ///< InnovationRecord::last_min_nis
  bool moment_plausible = true;   ///< TransmitterFilter::moment_plausible
  /// InnovationRecord::ratio_over(SearchConfig::confirm_innovation_window)
  double sustained_innovation_ratio = 0.0;
  /// Chi-square probability of the probe samples' NIS sum (SearchConfig::confirm_probe_window;
  /// 0 without any): near 1, they do not fit the estimate.
  double probe_nis_probability = 0.0;
  /// TransmitterFilter::window_reaches(confirm_window_reach_factor x the located radius), asked
  /// only of an estimate whose 95 % radius is already within its located radius (false
  /// otherwise): the latest samples alone allow the victim too far off to confirm it.
  bool window_reaches_farther = false;
};

class SearchController {
 public:
  explicit SearchController(SearchConfig config = {});

  /// The primary search's line lies `bearing_rad` from the rescuer's heading now (RescuerSearch
  /// turns it with the odometry from the first pulse the device heard). A controller that has
  /// not guided yet takes it as its line; without it, the line is the heading at its first
  /// guidance. A signal searched after another's victim opens along the primary line, not
  /// wherever the previous fine search left the rescuer facing (seen live: a third victim 26 m
  /// ahead of the first two unfound after 300 s, the rescuers walking off east and south).
  void primary_line_at(double bearing_rad) { primary_line_bearing_ = bearing_rad; }
  /// Guidance after the filter processed `measurement` (the same signal).
  Guidance guide(const TransmitterFilter& filter, const FieldMeasurement& measurement);
  /// Guidance for a step in which the signal was not heard (a pulse period up to 1.3 s, a pulse
  /// below the detection threshold, a lost sample). Farther than coast_return_m from where the
  /// last sample was taken, head back there, all the way (until a step from it or a sample
  /// arrives). Otherwise, in the opening search, keep walking straight on (the ring's mean says little
  /// yet); after it, head for the mixture moved by the odometry since
  /// (TransmitterFilter::predicted_moments). Ids and stamp are left for the caller.
  /// `device_quiet_epochs`: epochs in a row in which the device heard no signal at all. The
  /// lost-signal re-plan waits for both this signal's silence and the device's: a signal masked
  /// by its neighbours' pulses is not out of range (a single transmitter's silence is the
  /// device's, hence the default).
  Guidance coast(const TransmitterFilter& filter,
                 std::uint32_t device_quiet_epochs = std::numeric_limits<std::uint32_t>::max());
  /// kLocated / kFound refinement of a filter estimate, given what its filter says (same
  /// criteria as guide(), except that guide() also needs found_confirmations in a row for kFound).
  EstimatorStatus assess(const VictimEstimate& estimate, const ConfirmationEvidence& evidence) const;
  /// What `filter` says about confirming its estimate at `relative_position` (the located
  /// radius there picks its probe samples).
  ConfirmationEvidence evidence(const TransmitterFilter& filter, const Vec3& relative_position) const;
  /// Enough samples, recent, probe and newest innovations within their gates, a moment the
  /// standard allows: an estimate that may be confirmed.
  bool confirmable(const ConfirmationEvidence& evidence) const;
  GuidanceMode mode() const { return mode_; }
  /// A FOUND this controller gave was withdrawn (RescuerSearch's found witness disagreed): back
  /// to the fine search, nothing confirmed, no probe pattern.
  void withdraw_found();
  /// The 95 % radius below which an estimate at `relative_position` counts as located.
  double located_radius(const Vec3& relative_position) const;
  const SearchConfig& config() const { return config_; }
  /// Probe points (offsets from the estimate, G_k axes) of the adaptive end; empty when none
  /// is being walked or was walked.
  const std::vector<Eigen::Vector2d>& probe_pattern() const { return pattern_; }
  /// Probe points visited so far (== probe_pattern().size() once it is complete).
  std::size_t probe_points_visited() const { return pattern_next_; }
  /// The search ended kFound by the adaptive end (a complete probe pattern).
  bool found_by_probe_pattern() const { return pattern_complete_; }
  /// Times the signal was lost while the estimate was wide and the primary line was swept again.
  std::uint32_t line_resumptions() const { return line_resumptions_; }

 private:
  SearchConfig config_;
  GuidanceMode mode_ = GuidanceMode::kOpening;
  int probe_turn_ = 0;
  std::optional<double> initial_r95h_;  ///< 95 % horizontal radius at the first guidance
  Eigen::Vector2d flux_dir_ = Eigen::Vector2d::Zero();  ///< smoothed flux-line direction in G
  std::optional<double> opening_heading_;  ///< posterior-bearing heading held in G
  std::uint32_t opening_samples_ = 0;      ///< samples guided in the opening search so far
  bool returning_ = false;                 ///< coasting back to where the signal was last heard
  std::optional<double> primary_heading_;  ///< heading (G) of the primary search's line
  std::optional<double> primary_line_bearing_;  ///< primary_line_at(): the line from the heading now
  bool left_opening_ = false;                   ///< the opening search ended once (approach or closer)
  bool resuming_line_ = false;             ///< signal lost while wide: sweeping the primary line again
  double line_heading_ = 0.0;              ///< heading (G) of the sweep: the primary line's, or its reverse
  std::uint32_t line_resumptions_ = 0;
  std::optional<StallDetector> stall_;     ///< fine-search watch (stall_window_steps > 0)
  std::vector<Eigen::Vector2d> pattern_;   ///< adaptive end: probe offsets from the estimate
  std::size_t pattern_next_ = 0;           ///< next probe point to walk to
  double pattern_radius95_ = 0.0;          ///< 3-D 95 % radius the pattern was laid out for
  bool pattern_complete_ = false;
  std::uint32_t found_streak_ = 0;         ///< consecutive guided samples that said "found"
  std::uint32_t confirm_waits_ = 0;        ///< coasts on the probe point since the last sample
  bool probe_point_pending_ = false;       ///< counted a pattern point whose sample is yet to come
  std::uint32_t coasts_since_sample_ = 0;  ///< epochs coasted since the last guided sample
  std::array<std::uint32_t, 8> recent_gaps_{};  ///< epochs coasted between the last 8 guided samples
  std::size_t gap_slot_ = 0;

  /// Takes the primary line (primary_line_at, or `yaw`) if it has none yet.
  void adopt_primary_line(double yaw);
  /// Heading along the primary line: the rescuer's own `yaw` while within kOnPrimaryLine of it,
  /// or once the opening search has ended (an opening re-entered keeps the approach's heading).
  double along_primary_line(double yaw) const;
  /// Adaptive end, in fine search: feeds the stall watch, lays out, walks or drops the probe
  /// pattern. Sets `heading`/`step` while a pattern is walked; true once it is complete.
  bool adaptive_end(const Eigen::Vector2d& mean_h, const Mat3& cov, double r95, double converged_radius,
                    bool below, double& heading, double& step);
  void drop_pattern();

  double flux_line_heading(const TransmitterFilter& filter, const FieldMeasurement& meas,
                           const Eigen::Vector2d& mean_h, const Vec3& psi);
  double posterior_bearing_heading(const TransmitterFilter& filter);
};

}  // namespace sarloc::avalanche
