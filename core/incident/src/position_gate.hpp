#pragma once
// The association gate's distance between two position estimates (VictimFusion).
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "sarloc/core/common/types.hpp"

namespace sarloc::incident {

// Squared Mahalanobis distance with summed covariances (independence assumed only for the gate:
// CI covariances are conservative, so the sum is too).
inline double mahalanobis2(const GaussianPosition& a, const GaussianPosition& b) {
  const Mat3 s = a.covariance + b.covariance;
  const Eigen::LDLT<Mat3> ldlt(0.5 * (s + s.transpose()));
  const Vec3 d = a.position - b.position;
  const double d2 = d.dot(ldlt.solve(d));
  return std::isfinite(d2) ? std::max(d2, 0.0) : std::numeric_limits<double>::infinity();
}

}  // namespace sarloc::incident
