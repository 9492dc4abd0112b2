#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <random>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/covariance_intersection.hpp"

namespace sarloc::incident {
namespace {

Mat3 random_spd(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, 1.0);
  Mat3 a;
  for (int i = 0; i < 9; ++i) a(i) = n(rng);
  return scale * (a * a.transpose() + 0.2 * Mat3::Identity());
}

double min_eig(const Mat3& m) {
  return Eigen::SelfAdjointEigenSolver<Mat3>(0.5 * (m + m.transpose())).eigenvalues().minCoeff();
}

TEST(CovarianceIntersection, IdenticalInputsGiveTheInput) {
  std::mt19937 rng(1);
  GaussianPosition g;
  g.position = Vec3(1.0, -2.0, 3.0);
  g.covariance = random_spd(rng, 1.0);
  for (CiWeighting w : {CiWeighting::kInverseTrace, CiWeighting::kMinTrace}) {
    const CiResult r = covariance_intersection({g, g, g, g}, w);
    EXPECT_TRUE(r.fused.position.isApprox(g.position, 1e-9));
    EXPECT_TRUE(r.fused.covariance.isApprox(g.covariance, 1e-9));  // not P/4
    double sum = 0.0;
    for (double x : r.weights) sum += x;
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
}

TEST(CovarianceIntersection, SingleInputAndErrors) {
  GaussianPosition g;
  g.position = Vec3(5, 6, 7);
  EXPECT_TRUE(covariance_intersection({g}).fused.position.isApprox(g.position));
  EXPECT_THROW(covariance_intersection({}), InputError);
  GaussianPosition bad = g;
  bad.covariance(2, 2) = -1.0;
  EXPECT_THROW(covariance_intersection({g, bad}), InputError);
  bad = g;
  bad.position.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(covariance_intersection({g, bad}), InputError);
}

TEST(CovarianceIntersection, InverseTraceWeights) {
  GaussianPosition a, b;
  a.covariance = Mat3::Identity();        // trace 3
  b.covariance = 2.0 * Mat3::Identity();  // trace 6
  b.position = Vec3(3.0, 0.0, 0.0);
  const CiResult r = covariance_intersection({a, b});
  ASSERT_EQ(r.weights.size(), 2u);
  EXPECT_NEAR(r.weights[0], 2.0 / 3.0, 1e-12);
  // P^-1 = 2/3 * I + 1/3 * 0.5 I = 5/6 I; x = P (0 + 1/3 * 0.5 * 3) = 6/5 * 0.5 = 0.6.
  EXPECT_TRUE(r.fused.covariance.isApprox(1.2 * Mat3::Identity(), 1e-12));
  EXPECT_NEAR(r.fused.position.x(), 0.6, 1e-12);
}

TEST(CovarianceIntersection, MinTraceNeverWorseThanBestSource) {
  std::mt19937 rng(2);
  for (int t = 0; t < 200; ++t) {
    GaussianPosition a, b, c;
    a.covariance = random_spd(rng, 1.0);
    b.covariance = random_spd(rng, 1.0);
    c.covariance = random_spd(rng, 3.0);
    const double best = std::min({a.covariance.trace(), b.covariance.trace(), c.covariance.trace()});
    const CiResult r = covariance_intersection({a, b, c}, CiWeighting::kMinTrace);
    EXPECT_LE(r.fused.covariance.trace(), best * (1.0 + 1e-9));
  }
}

// Not overconfident: when every source is at best as good as source 0 (P_i >= P_0), no fusion
// of possibly fully correlated copies may claim better than P_0.
TEST(CovarianceIntersection, NeverMoreConfidentThanBestNestedSource) {
  std::mt19937 rng(3);
  for (int t = 0; t < 200; ++t) {
    std::vector<GaussianPosition> in(4);
    in[0].covariance = random_spd(rng, 1.0);
    for (std::size_t i = 1; i < in.size(); ++i)
      in[i].covariance = in[0].covariance + random_spd(rng, 0.5);
    for (CiWeighting w : {CiWeighting::kInverseTrace, CiWeighting::kMinTrace}) {
      const CiResult r = covariance_intersection(in, w);
      EXPECT_GE(min_eig(r.fused.covariance - in[0].covariance), -1e-9);
    }
  }
}

// Consistency under unknown correlation: two sources whose errors have cross-covariance
// rho * L1 L2^T (rho in [-1, 1]); the actual fused error covariance (analytic, and sampled by
// Monte Carlo, seed 001) must stay below the CI covariance.
TEST(CovarianceIntersection, ConsistentWithCorrelatedSourcesMonteCarlo) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int t = 0; t < 40; ++t) {
    const Mat3 p1 = random_spd(rng, 1.0), p2 = random_spd(rng, 1.0);
    const Mat3 l1 = Eigen::LLT<Mat3>(p1).matrixL(), l2 = Eigen::LLT<Mat3>(p2).matrixL();
    const double rho = std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
    GaussianPosition a, b;
    a.covariance = p1;
    b.covariance = p2;
    for (CiWeighting w : {CiWeighting::kInverseTrace, CiWeighting::kMinTrace}) {
      const CiResult r = covariance_intersection({a, b}, w);
      const Mat3& p = r.fused.covariance;
      const Mat3 k1 = r.weights[0] * p * p1.inverse(), k2 = r.weights[1] * p * p2.inverse();
      const Mat3 p12 = rho * l1 * l2.transpose();
      const Mat3 actual = k1 * p1 * k1.transpose() + k2 * p2 * k2.transpose() +
                          k1 * p12 * k2.transpose() + k2 * p12.transpose() * k1.transpose();
      EXPECT_GE(min_eig(p - actual), -1e-9) << "rho " << rho;
      // Monte Carlo: e1 = L1 z1, e2 = L2 (rho z1 + sqrt(1 - rho^2) z2).
      constexpr int kSamples = 4000;
      Mat3 sample = Mat3::Zero();
      for (int s = 0; s < kSamples; ++s) {
        Vec3 z1(n01(rng), n01(rng), n01(rng)), z2(n01(rng), n01(rng), n01(rng));
        const Vec3 e1 = l1 * z1, e2 = l2 * (rho * z1 + std::sqrt(1.0 - rho * rho) * z2);
        const Vec3 e = k1 * e1 + k2 * e2;  // fused error (the weights do not depend on data)
        sample += e * e.transpose();
      }
      sample /= kSamples;
      // Sampling error of a 4000-sample covariance: allow 10 % of the scale.
      EXPECT_GE(min_eig(p - sample), -0.1 * p.trace() / 3.0) << "rho " << rho;
    }
  }
}

// The reason for CI: a naive independent (information-sum) fusion of correlated copies is
// overconfident; CI is not. NEES over Monte Carlo draws of fully correlated sources.
TEST(CovarianceIntersection, NeesStaysBoundedWhereNaiveFusionFails) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n01(0.0, 1.0);
  const Mat3 p = Vec3(2.25, 2.25, 6.25).asDiagonal();
  const Mat3 l = Eigen::LLT<Mat3>(p).matrixL();
  double nees_ci = 0.0, nees_naive = 0.0;
  constexpr int kRuns = 2000;
  for (int r = 0; r < kRuns; ++r) {
    const Vec3 common = l * Vec3(n01(rng), n01(rng), n01(rng));  // shared GNSS error
    std::vector<GaussianPosition> in(3);
    for (auto& g : in) {
      g.covariance = p + 0.04 * Mat3::Identity();
      g.position = common + 0.2 * Vec3(n01(rng), n01(rng), n01(rng));
    }
    const CiResult ci = covariance_intersection(in);
    nees_ci += ci.fused.position.dot(ci.fused.covariance.inverse() * ci.fused.position);
    const Mat3 naive = in[0].covariance / 3.0;
    nees_naive += ci.fused.position.dot(naive.inverse() * ci.fused.position);
  }
  nees_ci /= kRuns;
  nees_naive /= kRuns;
  EXPECT_LT(nees_ci, 3.0 * 1.1);    // E[NEES] <= 3 for a consistent estimator
  EXPECT_GT(nees_naive, 3.0 * 2.0);  // the independent-sum fusion claims 3x too much
}

}  // namespace
}  // namespace sarloc::incident
