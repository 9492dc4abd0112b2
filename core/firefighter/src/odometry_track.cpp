#include "sarloc/core/firefighter/odometry_track.hpp"

#include <cmath>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::firefighter {

OdometryTrack::OdometryTrack(PatternMatchConfig config) : config_((config.validate(), config)) {}

void OdometryTrack::add(const Eigen::Vector3d& position) {
  if (!position.allFinite()) throw InputError("odometry position: not finite");
  const Vec2 p = position.head<2>();
  if (!points_.empty()) walked_ += (p - points_.back()).norm();
  points_.push_back(p);
  along_.push_back(walked_);
  // Keep a little more than one pattern length.
  while (along_.size() > 2 && walked_ - along_[1] > config_.pattern_length_m) {
    points_.pop_front();
    along_.pop_front();
  }
}

bool OdometryTrack::comparison_due() const {
  return walked_ >= config_.pattern_length_m && walked_ - compared_at_ >= config_.compare_every_m;
}

void OdometryTrack::compared() { compared_at_ = walked_; }

std::vector<Vec2> OdometryTrack::recent() const { return {points_.begin(), points_.end()}; }

double OdometryTrack::walk_heading() const {
  for (std::size_t k = points_.size(); k-- > 1;) {
    if (walked_ - along_[k - 1] >= 1.0 || k == 1) {
      const Vec2 d = points_.back() - points_[k - 1];
      return std::atan2(d.y(), d.x());
    }
  }
  return 0.0;
}

}  // namespace sarloc::firefighter
