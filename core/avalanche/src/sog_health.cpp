// The SOG filter's health tests: the leap test against its anchor, and whether a converged
// mixture pinned down something a buried transmitter could be.
#include "sarloc/core/avalanche/sog_filter.hpp"

#include <cmath>

#include "sarloc/core/avalanche/rotation.hpp"

#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {
using namespace sog_detail;  // the shared private helpers (sog_filter_detail.hpp)


void SogFilter::move_anchor(const Displacement& disp) {
  if (!anchor_ || disp.samples == 0) return;
  const Vec3 before = anchor_->position;
  anchor_->position = moved_point(moments(), before, disp.mean);
  // The step's translation noise, and its heading noise turning the anchor about the rescuer.
  const double yaw_var = disp.covariance(idx::kRot + 2, idx::kRot + 2);
  anchor_->covariance += disp.covariance.block<3, 3>(idx::kTrans, idx::kTrans);
  anchor_->covariance.topLeftCorner<2, 2>() += yaw_var * before.head<2>().squaredNorm() * Eigen::Matrix2d::Identity();
}

double SogFilter::leap_from_anchor() {
  const MixtureMoments mm = moments();
  const Vec3 mean = mm.mean.segment<3>(idx::kPos);
  const Mat3 cov = mm.covariance.block<3, 3>(idx::kPos, idx::kPos);
  double d2 = 0.0;
  if (anchor_) {
    const Vec3 d = mean - anchor_->position;
    d2 = d.dot((anchor_->covariance + cov).ldlt().solve(d));
  }
  if (!anchor_ || cov.trace() < 0.5 * anchor_->covariance.trace()) anchor_ = PositionAnchor{mean, cov};
  return d2;
}

bool SogFilter::pinned_down_plausibly() const {
  const MixtureMoments mm = moments();
  const double z = mm.mean[idx::kPos + 2];
  const double sd_z = std::sqrt(std::max(0.0, mm.covariance(idx::kPos + 2, idx::kPos + 2)));
  return z + 2.0 * sd_z < 0.0 && moment_plausible();
}

bool SogFilter::moment_plausible() const {
  return !components_.empty() && moment_plausible_from(moments(), config_.standard, config_.moment_margin);
}

}  // namespace sarloc::avalanche
