#pragma once
// The cross-product matrix, shared by the avalanche and firefighter estimators.
#include "sarloc/core/common/types.hpp"

namespace sarloc {

/// [v]x such that skew(v) * u = v.cross(u).
inline Mat3 skew(const Vec3& v) {
  Mat3 s;
  s << 0.0, -v.z(), v.y(),  //
      v.z(), 0.0, -v.x(),   //
      -v.y(), v.x(), 0.0;
  return s;
}

}  // namespace sarloc
