#pragma once
// Roll/pitch/yaw helpers for the ZYX convention of seed 000, eq. (2):
//   R = Rz(yaw) Ry(pitch) Rx(roll),   rpy = [roll, pitch, yaw].
//
// World angular velocity per Euler rate: a small change dPsi of the angles rotates R by
//   dR = [omega]x R,  omega = euler_rate_to_world(Psi) * dPsi,
// with euler_rate_to_world(Psi) = [[cy*cp, -sy, 0], [sy*cp, cy, 0], [-sp, 0, 1]].
// Every orientation Jacobian in the avalanche models is built from these two matrices.
#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/skew.hpp"
#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

/// Sines and cosines of roll, pitch, yaw, computed once and shared by R, E_w and E_w^-1
/// (the SOG filter's inner loop would otherwise evaluate the same trigonometry five times).
struct EulerTrig {
  double cr, sr, cp, sp, cy, sy;
  static EulerTrig from_rpy(const Vec3& rpy);
  /// From a rotation matrix without trigonometric calls (cos(pitch) >= 0 branch).
  static EulerTrig from_rotation(const Mat3& r);
  Mat3 rotation() const;
  Mat3 rate_to_world() const;
  Mat3 world_to_rate() const;
};

/// R = Rz(yaw) Ry(pitch) Rx(roll).
Mat3 rotation_from_rpy(const Vec3& rpy);

/// Inverse of rotation_from_rpy, pitch in [-pi/2, pi/2], roll and yaw in (-pi, pi].
Vec3 rpy_from_rotation(const Mat3& r);

/// E_w(Psi): world angular velocity per Euler-angle rate (see header comment).
Mat3 euler_rate_to_world(const Vec3& rpy);

/// E_w(Psi)^-1 in closed form (singular at pitch = +-pi/2, never reached by a hand-held receiver).
Mat3 world_to_euler_rate(const Vec3& rpy);


using sarloc::wrap_angle;  // core/common/angle.hpp

}  // namespace sarloc::avalanche
