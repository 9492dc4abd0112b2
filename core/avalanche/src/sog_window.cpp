// The SOG filter's window of latest samples, and whether they alone allow the transmitter a
// given distance from its estimate (SogConfig::window_fit_samples, dipole_window_fit.hpp).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {
using namespace sog_detail;  // the shared private helpers (sog_filter_detail.hpp)

namespace {

// Fewer samples than a confirmation asks for (SearchConfig::confirm_min_samples) say nothing.
constexpr std::size_t kMinWindowSamples = 10;

}  // namespace

void SogFilter::move_window(const MixtureMoments& mm, const Displacement& disp) {
  if (window_.empty() || disp.samples == 0) return;
  // As the anchor: the step's translation noise, and its heading noise turning the sample
  // about the rescuer.
  const double trans_var = disp.covariance.block<3, 3>(idx::kTrans, idx::kTrans).trace() / 3.0;
  const double yaw_var = disp.covariance(idx::kRot + 2, idx::kRot + 2);
  for (WindowSample& s : window_) {
    const Vec3 before = s.antenna;
    s.antenna = moved_point(mm, before, disp.mean);
    s.position_variance += trans_var + yaw_var * before.head<2>().squaredNorm();
  }
}

void SogFilter::remember_sample(const Vec3& field, const Vec3& floor, std::uint8_t axes) {
  if (config_.window_fit_samples == 0) return;
  WindowSample s;
  s.field = valid_axes_only(field, axes);
  s.floor = floor;
  s.axes = axes;
  // The frames G_k are ENU-aligned: the receiver's attitude in the current frame is its attitude
  // in every later one; only the antenna moves (move_window).
  s.rotation = rotation_from_rpy(moments().mean.segment<3>(idx::kAtt));
  window_.push_back(s);
  while (window_.size() > config_.window_fit_samples) window_.pop_front();
}

bool SogFilter::window_reaches(double distance) const {
  if (config_.window_fit_samples == 0 || !initialised() ||
      window_.size() < std::min<std::size_t>(kMinWindowSamples, config_.window_fit_samples))
    return false;
  if (reach_cache_ && reach_cache_->update == updates_ && reach_cache_->distance == distance)
    return reach_cache_->reaches;
  const MixtureMoments mm = moments();
  const Vec3 mean = mm.mean.segment<3>(idx::kPos);
  const DipoleWindowFit fitter(DipoleFitModel{config_.wavenumber(), config_.noise(), config_.calibration_variance()},
                               std::vector<WindowSample>(window_.begin(), window_.end()), mean);
  const auto best = fitter.fit(mean, mm.mean.segment<3>(idx::kMom));
  bool reaches = true;  // no dipole fits the window: it holds no radius
  if (best) {
    // The window's 95 % region (profile likelihood: the moment free at every point) is tried
    // where the fit's principal axes, and the line through the filter's mean, cross the sphere of
    // `distance` about the mean. Near a deep victim the region is a banana (depth and horizontal
    // offset trade against the moment), which the fit's covariance alone understates.
    const double level = chi_square_quantile(config_.window_region_probability, 3.0);
    auto inside = [&](const Vec3& at) {
      const auto f = fitter.fit_moment(at, best->moment);
      return f && f->deviance - best->deviance < level;
    };
    const Vec3 w = best->position - mean;
    reaches = w.norm() >= distance;
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(best->covariance.topLeftCorner<3, 3>());
    std::vector<Vec3> directions;
    for (int k = 0; k < 3; ++k) {
      directions.push_back(eig.eigenvectors().col(k));
      directions.push_back(-eig.eigenvectors().col(k));
    }
    if (w.norm() > 1e-6) {
      directions.push_back(-w.normalized());
      directions.push_back(w.normalized());
    }
    for (std::size_t k = 0; k < directions.size() && !reaches; ++k) {
      // |w + t u| = distance, t > 0 (the best is inside the sphere).
      const double wu = w.dot(directions[k]);
      const double t = -wu + std::sqrt(std::max(0.0, wu * wu - w.squaredNorm() + distance * distance));
      reaches = inside(best->position + t * directions[k]);
    }
  }
  reach_cache_ = ReachCache{updates_, distance, reaches};
  return reaches;
}

}  // namespace sarloc::avalanche
