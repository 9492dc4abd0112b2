#include "sarloc/core/avalanche/search_controller.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sarloc/core/avalanche/bearing_density.hpp"
#include "sarloc/core/avalanche/probe_pattern.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche {
namespace {

void check(const char* key, double v, double lo, double hi, bool lo_open) {
  const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
  require(ok, std::string("search.") + key, v,
          std::string("must be in ") + (lo_open ? "(" : "[") + config_value(lo) + ", " + config_value(hi) + "]");
}

/// A probe pattern is laid out for the 95 % radius of its moment; once the radius has grown
/// by half over it (a late innovation, a re-initialisation) the pattern no longer covers the
/// region and is dropped: the stall watch starts again and lays out a new one if needed.
constexpr double kPatternRegrowth = 1.5;

/// Epochs without a sample that a rescuer confirming a FOUND, or walking a probe pattern, waits
/// on a probe point: a period is at most 1.3 s, so three say the signal is not heard there,
/// unless its samples have lately come further apart (pulses lost under other victims'): then
/// as long as the longest recent gap, up to SearchConfig::confirm_max_waits epochs.
constexpr std::uint32_t kConfirmWaits = 3;

/// A rescuer heading within this of the primary line walks on straight: steering onto it at
/// every attitude update would make him dither, and walking straight is what makes the field
/// magnitude informative.
constexpr double kOnPrimaryLine = 20.0 * kPi / 180.0;

/// Within this distance (m) of a probe point the rescuer stands on it: no step is needed.
constexpr double kOnProbePoint = 0.01;

/// A buried victim is below the receiver, which is held above the snow. An estimate above it
/// is the mirror solution of a filter that has lost the victim (H(r) = H(-r)); its 95 %
/// radius can still look "located" (seen under packet loss: "found" 30 m up).
bool below_receiver(const Vec3& position, const Mat3& covariance) {
  return position.z() + 2.0 * std::sqrt(std::max(covariance(2, 2), 0.0)) < 0.0;
}

}  // namespace

void SearchConfig::validate() const {
  check("step_length_m", step_length_m, 0.0, 10.0, true);
  check("approach_mahalanobis", approach_mahalanobis, 0.0, 100.0, false);
  check("fine_search_radius_m", fine_search_radius_m, 0.0, 50.0, false);
  check("located_radius_m", located_radius_m, 0.0, 50.0, true);
  check("located_radius_per_range", located_radius_per_range, 0.0, 1.0, false);
  check("located_radius_max_m", located_radius_max_m, 0.0, 50.0, true);
  require(located_radius_max_m >= located_radius_m, "search.located_radius_max_m", located_radius_max_m,
          "must be at least search.located_radius_m (" + config_value(located_radius_m) + ")");
  check("found_distance_m", found_distance_m, 0.0, 50.0, true);
  check("confirm_min_samples", confirm_min_samples, 1.0, 1000.0, false);
  check("confirm_max_innovation_ratio", confirm_max_innovation_ratio, 0.0, 100.0, true);
  check("confirm_max_last_nis", confirm_max_last_nis, 0.0, 1000.0, true);
  check("confirm_innovation_window", confirm_innovation_window, 1.0, static_cast<double>(InnovationRecord::kHistory), false);
  check("confirm_probe_window", confirm_probe_window, 1.0, static_cast<double>(InnovationRecord::kHistory), false);
  check("confirm_probe_gate_probability", confirm_probe_gate_probability, 0.5, 1.0, true);
  check("confirm_window_reach_factor", confirm_window_reach_factor, 0.0, 100.0, false);
  check("found_confirmations", found_confirmations, 1.0, 20.0, false);
  check("confirm_probe_per_depth", confirm_probe_per_depth, 0.0, 2.0, false);
  check("confirm_max_waits", confirm_max_waits, static_cast<double>(kConfirmWaits), 600.0, false);
  check("probe_step_m", probe_step_m, 0.0, 10.0, true);
  check("approach_radius_fraction", approach_radius_fraction, 0.0, 1.0, true);
  check("flux_smoothing", flux_smoothing, 0.0, 0.99, false);
  check("opening_line_samples", opening_line_samples, 0.0, 100.0, false);
  check("coast_return_m", coast_return_m, 1.0, 1000.0, false);
  check("lost_signal_steps", lost_signal_steps, 0.0, 1000.0, false);
  check("lost_line_half_length_m", lost_line_half_length_m, 1.0, 1000.0, false);
  check("flux_snr_cap", flux_snr_cap, 0.0, 1000.0, true);
  check("flux_detection_snr2", flux_detection_snr2, 0.0, 100.0, false);
  check("bearing_kernel_deg", bearing_kernel_deg, 0.0, 180.0, true);
  check("bearing_switch_ratio", bearing_switch_ratio, 1.0, 100.0, false);
  check("stall_window_steps", stall_window_steps, 0.0, 1000.0, false);
  check("stall_min_improvement", stall_min_improvement, 0.0, 0.5, false);
  lookahead.validate();
}

const char* to_string(OpeningHeading h) {
  switch (h) {
    case OpeningHeading::kFluxLine: return "flux_line";
    case OpeningHeading::kLookahead: return "lookahead";
    case OpeningHeading::kPosteriorBearing: break;
  }
  return "posterior_bearing";
}

OpeningHeading parse_opening_heading(const std::string& text) {
  if (text == "posterior_bearing") return OpeningHeading::kPosteriorBearing;
  if (text == "flux_line") return OpeningHeading::kFluxLine;
  if (text == "lookahead") return OpeningHeading::kLookahead;
  throw ConfigError("search.opening_heading = '" + text +
                    "': must be posterior_bearing, flux_line or lookahead");
}

SearchController::SearchController(SearchConfig config) : config_(config) { config_.validate(); }

double SearchController::located_radius(const Vec3& relative_position) const {
  // Position precision degrades with range (|H| ~ 1/r^3: a relative field error gives a
  // relative range error), so a deep burial can never reach a fixed radius that suits a
  // shallow one (measured: a 5.6 m burial estimated to 0.15 m, 95 % radius stalled at 0.48 m).
  // Capped: far off, a radius that large is a guess, not a place to dig.
  return std::min(config_.located_radius_max_m,
                  std::max(config_.located_radius_m, config_.located_radius_per_range * relative_position.norm()));
}

ConfirmationEvidence SearchController::evidence(const TransmitterFilter& filter, const Vec3& relative_position) const {
  const InnovationRecord& record = filter.innovations();
  ConfirmationEvidence e{filter.mixture_samples(), record.recent_ratio(), record.last_min_nis(),
                         filter.moment_plausible(), record.ratio_over(config_.confirm_innovation_window)};
  const InnovationRecord::Sum probe = record.within(located_radius(relative_position), config_.confirm_probe_window);
  // A NaN sum (a numerically failed update) is no evidence of fit: probability 1, not a throw.
  if (probe.dof > 0.0) e.probe_nis_probability = probe.nis >= 0.0 ? chi_square_cdf(probe.nis, probe.dof) : 1.0;
  // The window fit costs about a millisecond: asked only once the radius is within the located
  // radius, where a confirmation could follow.
  const double located = located_radius(relative_position);
  const Mat3 cov = filter.moments().covariance.block<3, 3>(idx::kPos, idx::kPos);
  if (config_.confirm_window_reach_factor > 0.0 && radius95_3d(cov) <= located)
    e.window_reaches_farther = filter.window_reaches(config_.confirm_window_reach_factor * located);
  return e;
}

bool SearchController::confirmable(const ConfirmationEvidence& evidence) const {
  return static_cast<double>(evidence.samples) >= config_.confirm_min_samples &&
         evidence.innovation_ratio <= config_.confirm_max_innovation_ratio &&
         evidence.sustained_innovation_ratio <= config_.confirm_max_innovation_ratio &&
         evidence.probe_nis_probability <= config_.confirm_probe_gate_probability &&
         evidence.last_nis <= config_.confirm_max_last_nis && evidence.moment_plausible;
}

EstimatorStatus SearchController::assess(const VictimEstimate& e, const ConfirmationEvidence& evidence) const {
  if (e.status == EstimatorStatus::kInitialising) return e.status;
  if (!confirmable(evidence)) return std::min(e.status, EstimatorStatus::kConverged);
  if (!below_receiver(e.relative.position, e.relative.covariance))
    return std::min(e.status, EstimatorStatus::kConverged);
  if (radius95_3d(e.relative.covariance) > located_radius(e.relative.position)) return e.status;
  // How far its latest samples alone allow the victim: a filter collapsed early on a wrong place
  // near a deep victim states a radius its samples do not hold (SogFilter::window_reaches).
  if (evidence.window_reaches_farther) return e.status;
  if (e.relative.position.head<2>().norm() <= config_.found_distance_m)
    return EstimatorStatus::kFound;
  return EstimatorStatus::kLocated;
}

double SearchController::flux_line_heading(const TransmitterFilter& filter, const FieldMeasurement& meas,
                                           const Eigen::Vector2d& mean_h, const Vec3& psi) {
  // Horizontal flux-line direction in G, weighted by its signal-to-noise ratio and
  // low-pass filtered: with a weak signal the measured direction is mostly noise and the
  // rescuer keeps walking straight (a baseline that makes |z| informative) instead of
  // dithering; with a strong one it follows the line. A flux line has no sense: keep the
  // sense of the running direction, the first one towards the mixture mean.
  const Vec3 h_g = rotation_from_rpy(psi) * meas.field;
  Eigen::Vector2d dir = h_g.head<2>();
  const FieldNoiseModel noise = filter.noise();
  const double sigma = noise.sigma(meas.field.norm(), noise.floor(meas.noise_stddev).maxCoeff());
  const double snr = dir.norm() / (std::sqrt(2.0) * sigma);
  if (flux_dir_.squaredNorm() == 0.0) {
    // Start walking towards the mixture mean (or straight ahead), with a tiny weight so
    // that any informative flux direction takes over, while pure noise keeps it straight.
    const Eigen::Vector2d start = mean_h.norm() > 0.0
                                      ? Eigen::Vector2d(mean_h.normalized())
                                      : Eigen::Vector2d(std::cos(psi.z()), std::sin(psi.z()));
    flux_dir_ = 1e-3 * start;
  }
  if (dir.norm() > 0.0) {
    dir.normalize();
    if (dir.dot(flux_dir_) < 0.0) dir = -dir;
    // Pure noise gives E[snr^2] = 1 on two axes: only the excess carries direction.
    const double w = std::clamp(snr * snr - config_.flux_detection_snr2, 0.0,
                                config_.flux_snr_cap * config_.flux_snr_cap);
    flux_dir_ = config_.flux_smoothing * flux_dir_ + w * dir;
    if (flux_dir_.norm() < 1e-3) flux_dir_ = 1e-3 * flux_dir_.normalized();
  }
  return std::atan2(flux_dir_.y(), flux_dir_.x());
}

double SearchController::posterior_bearing_heading(const TransmitterFilter& filter) {
  const BearingDensity density(filter.hypotheses(), config_.bearing_kernel_deg * kPi / 180.0);
  const double peak = density.peak();
  if (!opening_heading_ || density.at(peak) > config_.bearing_switch_ratio * density.at(*opening_heading_))
    opening_heading_ = peak;
  return *opening_heading_;
}

Guidance SearchController::guide(const TransmitterFilter& filter, const FieldMeasurement& meas) {
  Guidance g;
  g.rescuer_id = meas.rescuer_id;
  g.signal_id = meas.signal_id;
  g.stamp = meas.stamp;
  returning_ = false;
  if (resuming_line_) {
    // Heard again on the primary line: the opening search starts over from here.
    resuming_line_ = false;
    mode_ = GuidanceMode::kOpening;
    opening_samples_ = 0;
    left_opening_ = false;  // a new opening, on the line
    initial_r95h_.reset();
    opening_heading_.reset();
  }
  recent_gaps_[gap_slot_++ % recent_gaps_.size()] = coasts_since_sample_;
  coasts_since_sample_ = 0;
  if (!filter.initialised()) {
    g.mode = mode_;
    g.step_m = 0.0;
    return g;
  }
  const MixtureMoments mm = filter.moments();
  const Vec3 mean = mm.mean.segment<3>(idx::kPos);
  const Mat3 cov = mm.covariance.block<3, 3>(idx::kPos, idx::kPos);
  const Vec3 psi = mm.mean.segment<3>(idx::kAtt);
  const double yaw = psi.z();
  const Eigen::Vector2d mean_h = mean.head<2>();
  const double dist = mean_h.norm();
  const double r95_h = radius95_2d(cov);
  adopt_primary_line(yaw);
  g.distance_m = dist;
  g.uncertainty_radius_m = r95_h;

  VictimEstimate e;
  e.status = EstimatorStatus::kMultimodal;
  e.relative.position = mean;
  e.relative.covariance = cov;
  const ConfirmationEvidence evidence = this->evidence(filter, mean);
  const bool may_confirm = confirmable(evidence);
  const EstimatorStatus st = assess(e, evidence);

  const Eigen::Matrix2d cov_h = cov.topLeftCorner<2, 2>();
  const double maha2 = mean_h.dot(cov_h.ldlt().solve(mean_h));
  const double thr2 = config_.approach_mahalanobis * config_.approach_mahalanobis;
  const double r95 = radius95_3d(cov);
  const bool below = below_receiver(mean, cov);
  // Complete or not, a pattern stands only for the estimate it was laid out for (seen: a
  // pattern completed around a mixture with an impossible moment said "found" for the ring
  // rebuilt 47 m wide, once that ring's moment was plausible).
  if (!pattern_.empty() && (r95 > kPatternRegrowth * pattern_radius95_ || !below)) drop_pattern();
  // Once a sample has said "found", the confirming samples are taken found_distance_m to either
  // side of the estimate: they count while the estimate stays located, and only where they were
  // taken beside it. Seen: a signal heard every third epoch, the rescuer back on the estimate
  // each time it was heard (coasting to it in between), confirmed 3.1 m from its victim by three
  // samples from one spot, a ghost (4 victims, seed 1, trial 6).
  const double probe_offset = std::max(config_.found_distance_m, config_.confirm_probe_per_depth * std::max(0.0, -mean.z()));
  const bool beside = dist >= 0.5 * probe_offset && dist <= 2.0 * probe_offset;
  const bool located = st == EstimatorStatus::kLocated || st == EstimatorStatus::kFound;
  const bool says_found = (found_streak_ == 0 ? st == EstimatorStatus::kFound : located && beside) ||
                          (pattern_complete_ && may_confirm);
  found_streak_ = says_found ? found_streak_ + 1 : 0;
  confirm_waits_ = 0;
  probe_point_pending_ = false;  // this sample was taken where the last guidance led
  const bool confirming = says_found && found_streak_ < config_.found_confirmations;
  if (says_found && !confirming) {
    mode_ = GuidanceMode::kFound;
  } else if (confirming) {
    mode_ = GuidanceMode::kFineSearch;
  } else if (!pattern_.empty()) {
    mode_ = GuidanceMode::kFineSearch;  // walking the probe pattern, wherever it leads
  } else if (mode_ == GuidanceMode::kOpening) {
    // The mean must be away from the receiver AND the data must have narrowed the initial
    // ring: with a signal at the noise floor the mean of a still-uniform ring only wanders.
    if (!initial_r95h_) initial_r95h_ = r95_h;
    const bool informative = r95_h <= config_.approach_radius_fraction * *initial_r95h_;
    if (maha2 > thr2 && informative) mode_ = GuidanceMode::kApproach;
  } else {
    // Back to the flux line only if the mixture spread out again around the receiver.
    if (maha2 <= thr2 && r95_h > config_.fine_search_radius_m) mode_ = GuidanceMode::kOpening;
    else mode_ = dist < config_.fine_search_radius_m ? GuidanceMode::kFineSearch
                                                     : GuidanceMode::kApproach;
  }
  if (mode_ != GuidanceMode::kOpening) left_opening_ = true;
  // The stall watch covers consecutive fine-search steps only.
  if (mode_ != GuidanceMode::kFineSearch && stall_) stall_->reset();

  double heading = std::atan2(mean_h.y(), mean_h.x());
  double step = config_.step_length_m;
  switch (mode_) {
    case GuidanceMode::kFound:
      step = 0.0;
      break;
    case GuidanceMode::kOpening:
      // A pulse or two at the edge of range is no direction yet (the ring is still whole and
      // the next pulse may not be heard): keep walking the primary search's line.
      if (++opening_samples_ <= config_.opening_line_samples) {
        heading = along_primary_line(yaw);
        break;
      }
      switch (config_.opening_heading) {
        case OpeningHeading::kFluxLine:
          heading = flux_line_heading(filter, meas, mean_h, psi);
          break;
        case OpeningHeading::kLookahead:
          heading = lookahead_heading(
              filter.hypotheses(), config_.lookahead, config_.step_length_m,
              filter.noise(), filter.noise().floor(meas.noise_stddev).maxCoeff());
          break;
        case OpeningHeading::kPosteriorBearing:
          heading = posterior_bearing_heading(filter);
          break;
      }
      break;
    case GuidanceMode::kApproach:
    case GuidanceMode::kPrimarySearch:  // never a signal's mode (strip_guidance.hpp)
      break;
    case GuidanceMode::kFineSearch:
      if (confirming) {
        // Said "found": the next samples are taken beside the estimate, alternately on either
        // side of the line to it, found_distance_m from it. A right estimate predicts the field
        // there; one that merely follows the rescuer (seen: a victim "found" 2 m off, under
        // another victim the rescuer stood on) fails the newest-sample gate.
        const Eigen::Vector2d along = dist > 1e-6 ? Eigen::Vector2d(mean_h / dist) : Eigen::Vector2d(1.0, 0.0);
        const Eigen::Vector2d across(-along.y(), along.x());
        const Eigen::Vector2d target =
            mean_h + (probe_turn_++ % 2 == 0 ? 1.0 : -1.0) * probe_offset * across;
        heading = std::atan2(target.y(), target.x());
        step = target.norm();
      } else if (config_.stall_window_steps > 0 &&
                 adaptive_end(mean_h, cov, r95, filter.converged_radius_m(), below, heading, step)) {
        // A complete pattern says "found" from the next sample on (found_confirmations in a row).
      } else if (dist > config_.found_distance_m) {
        step = std::min(step, dist);
      } else {
        // On top of the estimate but not located: a short sideways probe to change geometry.
        heading += 0.5 * kPi * (1 + 2 * (probe_turn_++ % 2));
        step = config_.probe_step_m;
      }
      break;
  }
  g.mode = mode_;
  g.heading_rad = wrap_angle(heading);
  g.bearing_rad = wrap_angle(heading - yaw);
  g.step_m = step;
  return g;
}

bool SearchController::adaptive_end(const Eigen::Vector2d& mean_h, const Mat3& cov, double r95,
                                    double converged_radius, bool below, double& heading, double& step) {
  if (pattern_.empty()) {
    if (!stall_) stall_.emplace(config_.stall_window_steps, config_.stall_min_improvement);
    // Stalled, and the estimate is one worth probing around: converged (a mixture whose modes
    // are still apart has a large radius) and below the receiver (not the mirror solution).
    if (!stall_->add(r95) || r95 > converged_radius || !below) return false;
    pattern_ = avalanche::probe_pattern(cov, config_.found_distance_m);  // the free function
    pattern_next_ = 0;
    pattern_radius95_ = r95;
  }
  // Offsets are from the current estimate: the pattern moves with it as the data refine it.
  while (pattern_next_ < pattern_.size() && (mean_h + pattern_[pattern_next_]).norm() <= kOnProbePoint)
    ++pattern_next_;  // standing on it: this sample was taken there
  if (pattern_next_ == pattern_.size()) {
    pattern_complete_ = true;
    step = 0.0;
    return true;
  }
  const Eigen::Vector2d target = mean_h + pattern_[pattern_next_];
  heading = std::atan2(target.y(), target.x());
  step = std::min(config_.step_length_m, target.norm());
  if (target.norm() <= config_.step_length_m) {
    ++pattern_next_;  // the next sample is taken there (coast() waits there for it)
    probe_point_pending_ = true;
  }
  return true;
}

void SearchController::withdraw_found() {
  mode_ = GuidanceMode::kFineSearch;
  found_streak_ = 0;
  confirm_waits_ = 0;
  drop_pattern();
}

void SearchController::drop_pattern() {
  pattern_.clear();
  pattern_next_ = 0;
  pattern_complete_ = false;
  probe_point_pending_ = false;
  pattern_radius95_ = 0.0;
  if (stall_) stall_->reset();
}

void SearchController::adopt_primary_line(double yaw) {
  // Without a line from the rescuer's search, he was walking it when this signal was first heard.
  if (!primary_heading_) primary_heading_ = primary_line_bearing_ ? wrap_angle(yaw + *primary_line_bearing_) : yaw;
}

double SearchController::along_primary_line(double yaw) const {
  // An opening re-entered after the approach (the mixture spread out again) keeps the heading the
  // approach gave: turning back to the line there walked away from the estimate (Table I's mean
  // steps rose 1.5-3 a seed).
  if (!primary_heading_ || left_opening_ || std::abs(wrap_angle(*primary_heading_ - yaw)) <= kOnPrimaryLine) return yaw;
  return *primary_heading_;
}

Guidance SearchController::coast(const TransmitterFilter& filter, std::uint32_t device_quiet_epochs) {
  const MixtureMoments mm = filter.predicted_moments();
  const Vec3 p = mm.mean.segment<3>(idx::kPos);
  Guidance g;
  g.mode = mode_ == GuidanceMode::kFound ? GuidanceMode::kApproach : mode_;
  g.distance_m = p.head<2>().norm();
  g.uncertainty_radius_m = radius95_2d(mm.covariance.block<3, 3>(idx::kPos, idx::kPos));
  g.heading_rad = std::atan2(p.y(), p.x());
  ++coasts_since_sample_;
  const std::uint32_t patience =
      std::clamp(*std::max_element(recent_gaps_.begin(), recent_gaps_.end()), kConfirmWaits, config_.confirm_max_waits);
  const bool waiting = mode_ == GuidanceMode::kFineSearch && (found_streak_ > 0 || probe_point_pending_);
  if (waiting && confirm_waits_ == patience && probe_point_pending_) {
    --pattern_next_;  // no sample was taken on that point of the pattern: it is walked again
    probe_point_pending_ = false;
  }
  if (waiting && confirm_waits_ < patience) {
    // Confirming, or walking a probe pattern: wait on the probe point for the signal's next
    // sample (a point visited without one says nothing: seen, a signal heard every eighth epoch
    // "completed" a pattern from one spot and was found 1.2 m off), but not for ever: a signal
    // not heard there (seen: a weak pulse under a strong one's, 800 s standing still) sends the
    // rescuer back to the estimate.
    ++confirm_waits_;
    g.bearing_rad = wrap_angle(g.heading_rad - mm.mean[idx::kAtt + 2]);
    g.step_m = 0.0;
    return g;
  }
  const double yaw = mm.mean[idx::kAtt + 2];
  adopt_primary_line(yaw);
  const bool wide = radius95_3d(mm.covariance.block<3, 3>(idx::kPos, idx::kPos)) > filter.converged_radius_m();
  if (config_.lost_signal_steps > 0 && primary_heading_ && wide && !resuming_line_ &&
      std::min(coasts_since_sample_, device_quiet_epochs) >= config_.lost_signal_steps) {
    resuming_line_ = true;
    returning_ = false;
    line_heading_ = *primary_heading_;
    ++line_resumptions_;
  }
  const Vec3 heard = filter.predicted_last_measurement_position();
  if (resuming_line_) {
    const Eigen::Vector2d along(std::cos(line_heading_), std::sin(line_heading_));
    if (heard.head<2>().norm() > config_.lost_line_half_length_m && heard.head<2>().dot(along) < 0.0)
      line_heading_ = wrap_angle(line_heading_ + kPi);
    g.mode = GuidanceMode::kOpening;
    g.heading_rad = line_heading_;
    g.bearing_rad = wrap_angle(line_heading_ - yaw);
    g.step_m = config_.step_length_m;
    return g;
  }
  const double back_m = heard.head<2>().norm();
  if (back_m > config_.coast_return_m) returning_ = true;
  if (back_m <= config_.step_length_m) returning_ = false;
  if (returning_) {
    g.bearing_rad = wrap_angle(std::atan2(heard.y(), heard.x()) - mm.mean[idx::kAtt + 2]);
    g.step_m = std::min(config_.step_length_m, heard.head<2>().norm());
  } else if (mode_ == GuidanceMode::kOpening) {
    g.bearing_rad = wrap_angle(along_primary_line(yaw) - yaw);
    g.step_m = config_.step_length_m;
  } else {
    g.bearing_rad = wrap_angle(g.heading_rad - mm.mean[idx::kAtt + 2]);
    g.step_m = std::min(config_.step_length_m, g.distance_m);
  }
  return g;
}

}  // namespace sarloc::avalanche
