#pragma once
// Simulated walks for the INS tests, as footfalls: straight 0.8 m strides, a heading per stride,
// and an optional flight of stairs (`rise_m` per stride from stride `climb_from` on: two
// 0.17 m risers per stride of one foot are 0.34 m).
#include <cmath>
#include <functional>
#include <vector>

#include "sarloc/core/firefighter/foot_trajectory.hpp"

namespace sarloc::firefighter::walks {

inline std::vector<Footfall> stride_walk(int strides, double standing_s, double stance_s,
                                         const std::function<double(int)>& yaw_of_stride, double rise_m = 0.0,
                                         int climb_from = 0) {
  std::vector<Footfall> feet(1);
  feet[0].stance_s = standing_s;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double t = standing_s;
  for (int k = 0; k < strides; ++k) {
    const double yaw = yaw_of_stride(k);
    p += 0.8 * Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0.0);
    if (k >= climb_from) p.z() += rise_m;
    Footfall f;
    f.t_land = t + 0.7;
    f.stance_s = stance_s;
    f.position = p;
    f.yaw = yaw;
    feet.push_back(f);
    t = f.t_land + f.stance_s;
  }
  return feet;
}

/// Straight strides with a 90-degree left turn every ten.
inline std::vector<Footfall> square_walk(int strides, double standing_s = 8.0, double rise_m = 0.0,
                                         int climb_from = 0) {
  return stride_walk(
      strides, standing_s, 0.9, [](int k) { return 0.5 * 3.14159265358979 * ((k + 1) / 10); }, rise_m, climb_from);
}

}  // namespace sarloc::firefighter::walks
