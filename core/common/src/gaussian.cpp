#include "sarloc/core/common/gaussian.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "sarloc/core/common/angle.hpp"

namespace sarloc {

double radius95_3d(const Mat3& covariance) {
  const double l = Eigen::SelfAdjointEigenSolver<Mat3>(covariance, Eigen::EigenvaluesOnly)
                       .eigenvalues()
                       .maxCoeff();
  return std::sqrt(kChi2_3_95 * std::max(l, 0.0));
}

double radius95_2d(const Mat3& covariance) {
  const Eigen::Matrix2d c = covariance.topLeftCorner<2, 2>();
  const double l = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(c, Eigen::EigenvaluesOnly)
                       .eigenvalues()
                       .maxCoeff();
  return std::sqrt(kChi2_2_95 * std::max(l, 0.0));
}

double log_normal_cdf(double u) {
  return u > -30.0 ? std::log(0.5 * std::erfc(-u / std::sqrt(2.0)))
                   : -0.5 * u * u - std::log(-u * std::sqrt(2.0 * kPi));
}

}  // namespace sarloc
