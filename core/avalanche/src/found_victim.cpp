#include "sarloc/core/avalanche/found_victim.hpp"

#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche {

double found_reach(const Mat3& covariance) { return radius95_3d(covariance) + kFalseFoundMarginM; }

std::optional<std::size_t> victim_of_found(const Vec3& found, double reach, const std::vector<Vec3>& victims,
                                           std::optional<std::size_t> own) {
  if (own && *own < victims.size() && (victims[*own] - found).norm() <= reach) return own;
  std::optional<std::size_t> nearest;
  double best = reach;
  for (std::size_t v = 0; v < victims.size(); ++v) {
    const double d = (victims[v] - found).norm();
    if (d <= best) {
      best = d;
      nearest = v;
    }
  }
  return nearest;
}

}  // namespace sarloc::avalanche
