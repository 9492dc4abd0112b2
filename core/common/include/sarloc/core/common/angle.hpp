#pragma once
// Pi, degrees, and one angle wrap for every estimator: particle headings, Euler yaw, guidance
// bearings.
#include <cmath>

namespace sarloc {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDeg = kPi / 180.0;  ///< radians per degree

/// Angle wrapped to (-pi, pi]. Inline: particle filters wrap every particle's heading at every
/// step, where atan2(sin, cos) cost a fifth of the firefighter filter's time.
inline double wrap_angle(double a) {
  if (a > -kPi && a <= kPi) return a;
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) a += 2.0 * kPi;
  return a - kPi;
}

}  // namespace sarloc
