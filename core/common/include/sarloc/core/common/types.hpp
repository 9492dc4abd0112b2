#pragma once
// Basic value types shared by every estimator in sarloc::core.
//
// Conventions (docs/topics.md repeats them for the wire format):
//   - time: int64 nanoseconds since the Unix epoch (TimestampNs);
//   - frames: incident frame is ENU (x east, y north, z up) around a geodetic origin;
//     a rescuer's geographic frame G is axis-aligned with the incident frame and centred
//     on the receiver antenna; the receiver frame R is x forward, y left, z up;
//   - orientation: roll/pitch/yaw, R = Rz(yaw) Ry(pitch) Rx(roll) (seed 000, eq. (2));
//   - covariances: full matrices, row-major on the wire.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace sarloc {

using TimestampNs = std::int64_t;

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Quat = Eigen::Quaterniond;

template <int Rows, int Cols>
using Jacobian = Eigen::Matrix<double, Rows, Cols>;

/// A 3-D position with its covariance (metres, m^2).
struct GaussianPosition {
  Vec3 position = Vec3::Zero();
  Mat3 covariance = Mat3::Identity();
};

/// A pose: position and orientation (unit quaternion, body to frame) with a 6x6 covariance
/// ordered [x y z roll pitch yaw] (m, rad).
struct GaussianPose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  Mat6 covariance = Mat6::Identity();
};

/// Geodetic origin of the incident (ENU) frame.
struct GeodeticOrigin {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double altitude_m = 0.0;
};

}  // namespace sarloc
