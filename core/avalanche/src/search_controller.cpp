#include "sarloc/core/avalanche/search_controller.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sarloc/core/avalanche/bearing_density.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche {
namespace {

void check(const char* key, double v, double lo, double hi, bool lo_open) {
  const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
  if (!ok) {
    std::ostringstream os;
    os << "search." << key << " = " << v << ": must be in " << (lo_open ? "(" : "[") << lo << ", "
       << hi << "]";
    throw ConfigError(os.str());
  }
}

}  // namespace

void SearchConfig::validate() const {
  check("step_length_m", step_length_m, 0.0, 10.0, true);
  check("approach_mahalanobis", approach_mahalanobis, 0.0, 100.0, false);
  check("fine_search_radius_m", fine_search_radius_m, 0.0, 50.0, false);
  check("located_radius_m", located_radius_m, 0.0, 50.0, true);
  check("located_radius_per_range", located_radius_per_range, 0.0, 1.0, false);
  check("found_distance_m", found_distance_m, 0.0, 50.0, true);
  check("probe_step_m", probe_step_m, 0.0, 10.0, true);
  check("approach_radius_fraction", approach_radius_fraction, 0.0, 1.0, true);
  check("flux_smoothing", flux_smoothing, 0.0, 0.99, false);
  check("flux_snr_cap", flux_snr_cap, 0.0, 1000.0, true);
  check("flux_detection_snr2", flux_detection_snr2, 0.0, 100.0, false);
  check("bearing_kernel_deg", bearing_kernel_deg, 0.0, 180.0, true);
  check("bearing_switch_ratio", bearing_switch_ratio, 1.0, 100.0, false);
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
  return std::max(config_.located_radius_m, config_.located_radius_per_range * relative_position.norm());
}

EstimatorStatus SearchController::assess(const VictimEstimate& e) const {
  if (e.status == EstimatorStatus::kInitialising) return e.status;
  // A buried victim is below the receiver, which is held above the snow. An estimate above it
  // is the mirror solution of a filter that has lost the victim (H(r) = H(-r)); its 95 %
  // radius can still look "located" (seen under packet loss: "found" 30 m up).
  if (!(e.relative.position.z() + 2.0 * std::sqrt(std::max(e.relative.covariance(2, 2), 0.0)) < 0.0))
    return std::min(e.status, EstimatorStatus::kConverged);
  if (radius95_3d(e.relative.covariance) > located_radius(e.relative.position)) return e.status;
  if (e.relative.position.head<2>().norm() <= config_.found_distance_m)
    return EstimatorStatus::kFound;
  return EstimatorStatus::kLocated;
}

double SearchController::flux_line_heading(const SogFilter& filter, const FieldMeasurement& meas,
                                           const Eigen::Vector2d& mean_h, const Vec3& psi) {
  // Horizontal flux-line direction in G, weighted by its signal-to-noise ratio and
  // low-pass filtered: with a weak signal the measured direction is mostly noise and the
  // rescuer keeps walking straight (a baseline that makes |z| informative) instead of
  // dithering; with a strong one it follows the line. A flux line has no sense: keep the
  // sense of the running direction, the first one towards the mixture mean.
  const Vec3 h_g = rotation_from_rpy(psi) * meas.field;
  Eigen::Vector2d dir = h_g.head<2>();
  const double sigma = filter.config().noise_relative * meas.field.norm() +
                       filter.noise_floor(meas).maxCoeff();
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

double SearchController::posterior_bearing_heading(const SogFilter& filter) {
  const BearingDensity density(filter.components(), config_.bearing_kernel_deg * kPi / 180.0);
  const double peak = density.peak();
  if (!opening_heading_ || density.at(peak) > config_.bearing_switch_ratio * density.at(*opening_heading_))
    opening_heading_ = peak;
  return *opening_heading_;
}

Guidance SearchController::guide(const SogFilter& filter, const FieldMeasurement& meas) {
  Guidance g;
  g.rescuer_id = meas.rescuer_id;
  g.signal_id = meas.signal_id;
  g.stamp = meas.stamp;
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
  g.distance_m = dist;
  g.uncertainty_radius_m = r95_h;

  VictimEstimate e;
  e.status = EstimatorStatus::kMultimodal;
  e.relative.position = mean;
  e.relative.covariance = cov;
  const EstimatorStatus st = assess(e);

  const Eigen::Matrix2d cov_h = cov.topLeftCorner<2, 2>();
  const double maha2 = mean_h.dot(cov_h.ldlt().solve(mean_h));
  const double thr2 = config_.approach_mahalanobis * config_.approach_mahalanobis;
  if (st == EstimatorStatus::kFound) {
    mode_ = GuidanceMode::kFound;
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
  g.mode = mode_;

  double heading = std::atan2(mean_h.y(), mean_h.x());
  double step = config_.step_length_m;
  switch (mode_) {
    case GuidanceMode::kFound:
      step = 0.0;
      break;
    case GuidanceMode::kOpening:
      switch (config_.opening_heading) {
        case OpeningHeading::kFluxLine:
          heading = flux_line_heading(filter, meas, mean_h, psi);
          break;
        case OpeningHeading::kLookahead:
          heading = lookahead_heading(
              filter.components(), config_.lookahead, config_.step_length_m,
              filter.config().noise_relative,
              filter.noise_floor(meas).maxCoeff());
          break;
        case OpeningHeading::kPosteriorBearing:
          heading = posterior_bearing_heading(filter);
          break;
      }
      break;
    case GuidanceMode::kApproach:
      break;
    case GuidanceMode::kFineSearch:
      if (dist > config_.found_distance_m) {
        step = std::min(step, dist);
      } else {
        // On top of the estimate but not located: a short sideways probe to change geometry.
        heading += 0.5 * kPi * (1 + 2 * (probe_turn_++ % 2));
        step = config_.probe_step_m;
      }
      break;
  }
  g.heading_rad = wrap_angle(heading);
  g.bearing_rad = wrap_angle(heading - yaw);
  g.step_m = step;
  return g;
}

}  // namespace sarloc::avalanche
