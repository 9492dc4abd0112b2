#pragma once
// The gait model of the IMU simulator: a boot's motion between footfalls. The foot stands still
// for the stance, then swings to the next footfall: minimum-jerk along the line between the two
// (seed-free textbook gait model), lifted and pitched by smooth bumps that vanish with their
// first derivative at lift-off and landing, yawed from one footfall's heading to the next.
// Everything is analytic, so the 100 Hz specific force and angular rate are exact.
//
//   FootTrajectory foot(footfalls);
//   std::vector<ImuSample> ideal = foot.imu_samples(100.0);   // then ImuErrors::apply
#include <cstddef>
#include <vector>

#include "sarloc/core/firefighter/imu_sample.hpp"

namespace sarloc::firefighter {

enum class Gait : std::uint8_t { kWalk, kCrawl };

struct Footfall {
  double t_land = 0.0;     ///< s: the foot touches down
  double stance_s = 0.5;   ///< s: and stays still this long (stops and sweeps lengthen it)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< m, z includes stairs
  double yaw = 0.0;        ///< rad, the boot's heading
  std::size_t floor = 0;
  Gait gait = Gait::kWalk; ///< of the swing that leaves this footfall
};

struct FootState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
  double yaw = 0.0, yaw_rate = 0.0, pitch = 0.0, pitch_rate = 0.0;
  std::size_t floor = 0;
  bool stance = true;
};

class FootTrajectory {
 public:
  /// Footfalls in time order, each swing at least 0.1 s (throws InputError otherwise).
  explicit FootTrajectory(std::vector<Footfall> footfalls);

  FootState at(double t) const;
  double end_time() const;
  /// Ideal samples at `rate_hz` from t = 0 to end_time(): R = Rz(yaw) Ry(pitch),
  /// f = R^T (a + g e_z), w = (-yaw' sin(pitch), pitch', yaw' cos(pitch)).
  std::vector<ImuSample> imu_samples(double rate_hz) const;
  const std::vector<Footfall>& footfalls() const { return footfalls_; }

 private:
  std::vector<Footfall> footfalls_;
};

}  // namespace sarloc::firefighter
