#include "sarloc/core/avalanche/rotation.hpp"

#include <algorithm>
#include <cmath>

namespace sarloc::avalanche {

EulerTrig EulerTrig::from_rpy(const Vec3& rpy) {
  return {std::cos(rpy.x()), std::sin(rpy.x()), std::cos(rpy.y()),
          std::sin(rpy.y()), std::cos(rpy.z()), std::sin(rpy.z())};
}

EulerTrig EulerTrig::from_rotation(const Mat3& r) {
  const double cp = std::sqrt(r(2, 1) * r(2, 1) + r(2, 2) * r(2, 2));
  const double inv = 1.0 / cp;
  return {r(2, 2) * inv, r(2, 1) * inv, cp, -r(2, 0), r(0, 0) * inv, r(1, 0) * inv};
}

Mat3 EulerTrig::rotation() const {
  Mat3 r;
  r << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return r;
}

Mat3 EulerTrig::rate_to_world() const {
  Mat3 e;
  e << cy * cp, -sy, 0.0,  //
      sy * cp, cy, 0.0,    //
      -sp, 0.0, 1.0;
  return e;
}

Mat3 EulerTrig::world_to_rate() const {
  const double tp = sp / cp;
  Mat3 e;
  e << cy / cp, sy / cp, 0.0,  //
      -sy, cy, 0.0,            //
      cy * tp, sy * tp, 1.0;
  return e;
}

Mat3 rotation_from_rpy(const Vec3& rpy) { return EulerTrig::from_rpy(rpy).rotation(); }

Vec3 rpy_from_rotation(const Mat3& r) {
  const double sp = std::clamp(-r(2, 0), -1.0, 1.0);
  return {std::atan2(r(2, 1), r(2, 2)), std::asin(sp), std::atan2(r(1, 0), r(0, 0))};
}

Mat3 euler_rate_to_world(const Vec3& rpy) { return EulerTrig::from_rpy(rpy).rate_to_world(); }

Mat3 world_to_euler_rate(const Vec3& rpy) { return EulerTrig::from_rpy(rpy).world_to_rate(); }

}  // namespace sarloc::avalanche
