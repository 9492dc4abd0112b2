#pragma once
// Rescuer displacement between two samples, expressed in the body/receiver frame at the start
// of the interval (seed 000, eq. (4): R_{k-1} x_{R_k}).
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::responder {

enum class OdometrySource : std::uint8_t { kSimulated = 0, kFootMountedIns = 1, kVisualInertial = 2, kOther = 3 };

struct Odometry {
  std::string rescuer_id;
  std::uint64_t sequence = 0;
  TimestampNs interval_start = 0;
  TimestampNs interval_end = 0;
  Vec3 translation = Vec3::Zero();   ///< m, in R_{k-1}
  Vec3 rotation_rpy = Vec3::Zero();  ///< roll, pitch, yaw of R_k in R_{k-1} (rad)
  Mat6 covariance = Mat6::Identity();///< order [tx ty tz roll pitch yaw]
  OdometrySource source = OdometrySource::kSimulated;
};

}  // namespace sarloc::responder
