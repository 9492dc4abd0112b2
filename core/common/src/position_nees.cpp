#include "sarloc/core/common/position_nees.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

namespace sarloc {

double position_nees(const Vec3& error, const Mat3& covariance) {
  const Eigen::LDLT<Mat3> ldlt(covariance);
  const double nees = ldlt.info() == Eigen::Success && ldlt.isPositive() ? error.dot(ldlt.solve(error)) : 0.0;
  if (!(nees >= 0.0) || !std::isfinite(nees) || (nees == 0.0 && error.squaredNorm() > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  return nees;
}

}  // namespace sarloc
