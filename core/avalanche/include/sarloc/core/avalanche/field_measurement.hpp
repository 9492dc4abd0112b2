#pragma once
// One 3-axis avalanche-beacon field sample, for one separated signal (one transmitter).
#include <optional>
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

/// Receiver orientation in the geographic frame G (roll, pitch, yaw in rad, seed 000 eq. (2))
/// from an attitude sensor, with its 3x3 covariance (rad^2).
struct OrientationObservation {
  Vec3 rpy = Vec3::Zero();
  Mat3 covariance = Mat3::Identity();
};

struct FieldMeasurement {
  std::string rescuer_id;
  std::uint32_t signal_id = 0;       ///< transmitter as separated by the receiver
  std::uint64_t sequence = 0;        ///< per (rescuer, signal), strictly increasing
  TimestampNs stamp = 0;
  Vec3 field = Vec3::Zero();         ///< magnetic field in the receiver antenna frame R (A/m)
  Vec3 noise_stddev = Vec3::Zero();  ///< per-axis 1-sigma noise (A/m)
  std::optional<OrientationObservation> orientation;
};

}  // namespace sarloc::avalanche
