// The shared Gaussian helpers: 95 % radii, log Phi, moment matching (eq. (18)).
#include "sarloc/core/common/gaussian.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sarloc/core/common/chi_square.hpp"

namespace sarloc {
namespace {

TEST(GaussianRadiusTest, ConstantsAreTheChiSquareQuantiles) {
  EXPECT_NEAR(kChi2_3_95, chi_square_quantile(0.95, 3.0), 1e-9);
  EXPECT_NEAR(kChi2_2_95, chi_square_quantile(0.95, 2.0), 1e-9);
  EXPECT_NEAR(kChi2_2_95, -2.0 * std::log(0.05), 1e-14);
  EXPECT_NEAR(kChi2_2_99, chi_square_quantile(0.99, 2.0), 1e-9);
  EXPECT_NEAR(kChi2_2_99, -2.0 * std::log(0.01), 1e-14);
  EXPECT_NEAR(kChi2_2_999, chi_square_quantile(0.999, 2.0), 1e-9);
  EXPECT_NEAR(kChi2_2_999, -2.0 * std::log(0.001), 1e-14);
}

TEST(GaussianRadiusTest, WorstAxisOfTheCovariance) {
  EXPECT_NEAR(radius95_3d(Mat3::Identity()), std::sqrt(7.814727903), 1e-6);
  Mat3 c = Vec3(0.04, 0.01, 0.25).asDiagonal();  // sigma 0.2, 0.1, 0.5 m
  EXPECT_NEAR(radius95_3d(c), 0.5 * std::sqrt(kChi2_3_95), 1e-12);
  // The horizontal radius ignores the vertical axis.
  EXPECT_NEAR(radius95_2d(c), 0.2 * std::sqrt(kChi2_2_95), 1e-12);
  // Rotated: the largest eigenvalue, not the largest diagonal entry.
  Mat3 r = Mat3::Zero();
  r.topLeftCorner<2, 2>() << 1.0, 0.8, 0.8, 1.0;  // eigenvalues 1.8, 0.2
  r(2, 2) = 0.1;
  EXPECT_NEAR(radius95_3d(r), std::sqrt(kChi2_3_95 * 1.8), 1e-12);
  EXPECT_NEAR(radius95_2d(r), std::sqrt(kChi2_2_95 * 1.8), 1e-12);
  EXPECT_EQ(radius95_3d(Mat3::Zero()), 0.0);
}

TEST(LogNormalCdfTest, ValuesAndTail) {
  EXPECT_NEAR(log_normal_cdf(0.0), std::log(0.5), 1e-15);
  EXPECT_NEAR(log_normal_cdf(-1.959963984540054), std::log(0.025), 1e-12);
  EXPECT_NEAR(log_normal_cdf(3.0), std::log(0.9986501019683699), 1e-13);
  // erfc underflows far in the tail; the asymptote takes over continuously at u = -30.
  EXPECT_TRUE(std::isfinite(log_normal_cdf(-40.0)));
  EXPECT_NEAR(log_normal_cdf(-30.0 - 1e-9), log_normal_cdf(-30.0 + 1e-9), 2e-3);
  EXPECT_LT(log_normal_cdf(-40.0), log_normal_cdf(-35.0));
}

TEST(MatchMomentsTest, MeanAndCovarianceOfAWeightedSet) {
  using V2 = Eigen::Vector2d;
  using M2 = Eigen::Matrix2d;
  const std::vector<V2> x = {V2(0.0, 0.0), V2(2.0, 0.0)};
  const std::vector<M2> p = {M2::Identity(), 3.0 * M2::Identity()};
  const std::vector<double> w = {1.0, 3.0};  // relative weights
  for (double base : {0.0, 5.0, -700.0}) {
    const GaussianMoments<2> m = match_moments<2>(
        2,
        [&](std::size_t k) { return WeightedGaussianRef<2>{std::log(w[k]) + base, x[k], p[k]}; },
        base);
    EXPECT_NEAR(m.weight_sum, 4.0, 1e-12);
    EXPECT_NEAR(m.mean.x(), 1.5, 1e-12);
    EXPECT_NEAR(m.mean.y(), 0.0, 1e-12);
    // Mean of the covariances (0.25 + 0.75 * 3 = 2.5) plus the spread of the means along x:
    // 0.25 * 1.5^2 + 0.75 * 0.5^2 = 0.75.
    EXPECT_NEAR(m.covariance(0, 0), 3.25, 1e-12);
    EXPECT_NEAR(m.covariance(1, 1), 2.5, 1e-12);
    EXPECT_NEAR(m.covariance(0, 1), 0.0, 1e-12);
  }
}

}  // namespace
}  // namespace sarloc
