#pragma once
// A GNSS receiver's fix as the receiver gives it (WGS-84 latitude, longitude and ellipsoidal
// height, with its 1-sigma accuracies), and the device's one conversion of it into the incident
// frame (GeodeticFrame). A rescuer's device reports positions in the incident frame; it takes
// its receiver's fixes in WGS-84, whether simulated or read from a recorded sensor file.
//
//   const GnssFix fix{stamp, {46.95, 7.45, 2100.0}, 2.5, 5.0};
//   const GaussianPosition p = in_incident_frame(frame, fix);  // InputError naming the field
#include "sarloc/core/common/types.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"

namespace sarloc::incident {

/// Farther than this from the incident's origin a fix is refused: no rescue is that wide, and
/// a receiver that says so is wrong (a first fix from a cold start, a bad almanac).
inline constexpr double kMaxFixDistanceM = 100'000.0;
/// A stated accuracy above this (or not positive) is refused: a fix that knows nothing.
inline constexpr double kMaxFixSigmaM = 1000.0;

struct GnssFix {
  TimestampNs stamp = 0;
  Geodetic position;
  double horizontal_sigma_m = 1.0;  ///< 1-sigma, east and north each
  double vertical_sigma_m = 2.0;    ///< 1-sigma, up
};

/// The fix in the incident frame, its covariance diag(h^2, h^2, v^2). InputError naming the
/// field and value for a coordinate out of range, an accuracy not in (0, kMaxFixSigmaM], or a
/// fix farther than kMaxFixDistanceM from the origin.
GaussianPosition in_incident_frame(const GeodeticFrame& frame, const GnssFix& fix);

/// What a receiver at `position` (incident frame) reports: the WGS-84 point and the 1-sigma
/// accuracies of the covariance (horizontal: the larger of east and north). The simulated
/// receiver's output, so simulated missions take the same path as a real device.
GnssFix as_receiver_fix(const GeodeticFrame& frame, TimestampNs stamp, const GaussianPosition& position);

}  // namespace sarloc::incident
