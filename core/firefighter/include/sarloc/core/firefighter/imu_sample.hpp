#pragma once
// One sample of a foot-mounted 6-DoF IMU: specific force and angular rate in the sensor frame
// (x forward along the boot, y left, z up), at time t (s since the start of the recording).
#include <Eigen/Core>

namespace sarloc::firefighter {

struct ImuSample {
  double t = 0.0;
  Eigen::Vector3d specific_force = Eigen::Vector3d::Zero();  ///< m/s^2 (reads +g up at rest)
  Eigen::Vector3d angular_rate = Eigen::Vector3d::Zero();    ///< rad/s
};

/// Standard gravity (m/s^2), the value the INS and the simulator share.
inline constexpr double kGravity = 9.81;

}  // namespace sarloc::firefighter
