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

Ellipse95 ellipse95(const Eigen::Matrix2d& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  const Eigen::Vector2d major = eigen.eigenvectors().col(1);  // eigenvalues ascend
  return {std::sqrt(kChi2_2_95 * std::max(0.0, eigen.eigenvalues()(1))),
          std::sqrt(kChi2_2_95 * std::max(0.0, eigen.eigenvalues()(0))), std::atan2(major.y(), major.x())};
}

std::vector<Eigen::Vector2d> ellipse95_outline(const Eigen::Vector2d& centre, const Eigen::Matrix2d& covariance,
                                               int points) {
  const Ellipse95 e = ellipse95(covariance);
  const Eigen::Vector2d major(std::cos(e.major_angle_rad), std::sin(e.major_angle_rad));
  const Eigen::Vector2d minor(-major.y(), major.x());  // major turned 90 degrees left: counter-clockwise
  std::vector<Eigen::Vector2d> outline;
  const int n = std::max(points, 3);
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * kPi * k / n;
    outline.push_back(centre + e.semi_major_m * std::cos(t) * major + e.semi_minor_m * std::sin(t) * minor);
  }
  return outline;
}

double log_normal_cdf(double u) {
  return u > -30.0 ? std::log(0.5 * std::erfc(-u / std::sqrt(2.0)))
                   : -0.5 * u * u - std::log(-u * std::sqrt(2.0 * kPi));
}

}  // namespace sarloc
