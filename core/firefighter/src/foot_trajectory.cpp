#include "sarloc/core/firefighter/foot_trajectory.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::firefighter {
namespace {

struct Profile {
  double f, d1, d2;  // value, first and second derivative in tau
};

// Minimum-jerk 0 -> 1 with zero velocity and acceleration at both ends.
Profile min_jerk(double s) {
  return {s * s * s * (10.0 - 15.0 * s + 6.0 * s * s), 30.0 * s * s * (1.0 - s) * (1.0 - s),
          60.0 * s * (1.0 - s) * (1.0 - 2.0 * s)};
}

// 64 s^3 (1-s)^3: a bump peaking at 1, flat (value and slope 0) at both ends.
Profile bump(double s) {
  const double u = 1.0 - s;
  return {64.0 * s * s * s * u * u * u, 192.0 * s * s * u * u * (1.0 - 2.0 * s),
          384.0 * s * u * ((1.0 - 2.0 * s) * (1.0 - 2.0 * s) - s * u)};
}

// Toe-off then heel-strike: (1 - 2s) bump(s), scaled to peak near +-1.
Profile pitch_shape(double s) {
  constexpr double kScale = 4.2;
  const Profile b = bump(s);
  const double l = 1.0 - 2.0 * s;
  return {kScale * l * b.f, kScale * (l * b.d1 - 2.0 * b.f), kScale * (l * b.d2 - 4.0 * b.d1)};
}


struct GaitShape {
  double lift_m;
  double pitch_rad;
};

GaitShape shape(Gait g) {
  // A search walk lifts the boot about 10 cm and rolls it through +-30 deg; crawling drags it.
  return g == Gait::kCrawl ? GaitShape{0.02, 0.1} : GaitShape{0.10, 0.5};
}

}  // namespace

FootTrajectory::FootTrajectory(std::vector<Footfall> footfalls) : footfalls_(std::move(footfalls)) {
  if (footfalls_.empty()) throw InputError("footfalls: at least one is required");
  for (std::size_t k = 0; k < footfalls_.size(); ++k) {
    const Footfall& f = footfalls_[k];
    if (!f.position.allFinite() || !std::isfinite(f.yaw) || !std::isfinite(f.t_land) || !(f.stance_s >= 0.0)) {
      throw InputError("footfalls[" + std::to_string(k) + "]: not finite");
    }
    if (k + 1 < footfalls_.size() && footfalls_[k + 1].t_land - (f.t_land + f.stance_s) < 0.1) {
      throw InputError("footfalls[" + std::to_string(k + 1) + "].t_land = " + std::to_string(footfalls_[k + 1].t_land) +
                       ": swing shorter than 0.1 s");
    }
  }
}

double FootTrajectory::end_time() const { return footfalls_.back().t_land + footfalls_.back().stance_s; }

FootState FootTrajectory::at(double t) const {
  // The last footfall landing at or before t.
  auto it = std::upper_bound(footfalls_.begin(), footfalls_.end(), t,
                             [](double v, const Footfall& f) { return v < f.t_land; });
  FootState s;
  if (it == footfalls_.begin()) {
    s.position = footfalls_.front().position;
    s.yaw = footfalls_.front().yaw;
    s.floor = footfalls_.front().floor;
    return s;
  }
  const Footfall& a = *(it - 1);
  s.floor = a.floor;
  const double lift_off = a.t_land + a.stance_s;
  if (it == footfalls_.end() || t <= lift_off) {
    s.position = a.position;
    s.yaw = a.yaw;
    return s;
  }
  const Footfall& b = *it;
  const double T = b.t_land - lift_off;
  const double tau = std::clamp((t - lift_off) / T, 0.0, 1.0);
  const Profile m = min_jerk(tau), lift = bump(tau), p = pitch_shape(tau);
  const GaitShape g = shape(a.gait);
  const Eigen::Vector3d d = b.position - a.position;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ() * g.lift_m;
  s.stance = false;
  s.position = a.position + m.f * d + lift.f * up;
  s.velocity = (m.d1 * d + lift.d1 * up) / T;
  s.acceleration = (m.d2 * d + lift.d2 * up) / (T * T);
  const double dyaw = wrap_angle(b.yaw - a.yaw);
  s.yaw = a.yaw + m.f * dyaw;
  s.yaw_rate = m.d1 * dyaw / T;
  s.pitch = g.pitch_rad * p.f;
  s.pitch_rate = g.pitch_rad * p.d1 / T;
  if (tau > 0.5) s.floor = b.floor;
  return s;
}

std::vector<ImuSample> FootTrajectory::imu_samples(double rate_hz) const {
  const double dt = 1.0 / rate_hz;
  const auto n = static_cast<std::size_t>(std::floor(end_time() * rate_hz)) + 1;
  std::vector<ImuSample> out;
  out.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    const FootState s = at(t);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(s.yaw, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(s.pitch, Eigen::Vector3d::UnitY()))
                                  .toRotationMatrix();
    ImuSample sample;
    sample.t = t;
    sample.specific_force = R.transpose() * (s.acceleration + kGravity * Eigen::Vector3d::UnitZ());
    sample.angular_rate = Eigen::Vector3d(-s.yaw_rate * std::sin(s.pitch), s.pitch_rate, s.yaw_rate * std::cos(s.pitch));
    out.push_back(sample);
  }
  return out;
}

}  // namespace sarloc::firefighter
