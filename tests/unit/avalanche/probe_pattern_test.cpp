// probe_pattern: probe points covering the horizontal 95 % region of an estimate.
#include "sarloc/core/avalanche/probe_pattern.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche {
namespace {

using Vec2 = Eigen::Vector2d;

// A position covariance whose horizontal 95 % ellipse has semi-axes a, b (m), the a axis at
// `angle` from x; vertical sigma 0.2 m (it plays no part).
Mat3 covariance_with_ellipse(double a, double b, double angle) {
  const double k2 = kChi2_2_95;
  Eigen::Matrix2d r;
  r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  const Eigen::Matrix2d d = Eigen::Vector2d(a * a / k2, b * b / k2).asDiagonal();
  Mat3 c = Mat3::Zero();
  c.topLeftCorner<2, 2>() = r * d * r.transpose();
  c(2, 2) = 0.04;
  return c;
}

double distance_to_pattern(const Vec2& x, const std::vector<Vec2>& pattern) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vec2& p : pattern) best = std::min(best, (x - p).norm());
  return best;
}

// Points uniformly inside the ellipse and on its boundary (where coverage is hardest).
std::vector<Vec2> points_of_ellipse(double a, double b, double angle, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Eigen::Rotation2Dd rot(angle);
  std::vector<Vec2> out;
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * kPi * u(rng);
    const double rho = i % 4 == 0 ? 1.0 : std::sqrt(u(rng));
    out.push_back(rot * Vec2(a * rho * std::cos(t), b * rho * std::sin(t)));
  }
  return out;
}

TEST(ProbePattern, ARegionInsideTheCoverRadiusIsTheEstimateAlone) {
  const auto pattern = probe_pattern(covariance_with_ellipse(0.5, 0.3, 0.7), 0.5);
  ASSERT_EQ(pattern.size(), 1u);
  EXPECT_EQ(pattern[0], Vec2::Zero());
  EXPECT_EQ(probe_pattern(Mat3::Zero(), 0.5).size(), 1u) << "a point estimate";
}

// Every point of the 95 % region lies within the cover radius of a probe point, for round,
// elongated, rotated and nearly degenerate regions; the pattern starts on the estimate and
// spirals outwards; it holds no point whose cell misses the region, and no more points than
// disjoint cells can fit near it.
TEST(ProbePattern, CoversTheRegionFromTheCentreOutwards) {
  struct Case {
    double a, b, angle, cover;
  };
  const Case cases[] = {{0.6, 0.6, 0.0, 0.5},  {1.0, 1.0, 0.3, 0.5},   {2.0, 0.3, 0.9, 0.5},
                        {1.7, 1.1, -2.0, 0.5}, {3.0, 0.001, 0.4, 0.5}, {1.2, 0.8, 0.2, 0.25}};
  std::uint64_t seed = 1;
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::Message() << "a " << c.a << " b " << c.b << " cover " << c.cover);
    const Mat3 cov = covariance_with_ellipse(c.a, c.b, c.angle);
    ASSERT_NEAR(radius95_2d(cov), c.a, 1e-9);
    const auto pattern = probe_pattern(cov, c.cover);
    ASSERT_GT(pattern.size(), 1u);
    EXPECT_EQ(pattern[0], Vec2::Zero());
    for (const Vec2& x : points_of_ellipse(c.a, c.b, c.angle, 20000, seed++)) {
      ASSERT_LE(distance_to_pattern(x, pattern), c.cover + 1e-9) << "uncovered point " << x.transpose();
    }
    // A hexagonal lattice of spacing sqrt(3) cover, walked ring by ring (a spiral).
    const double s = std::sqrt(3.0) * c.cover;
    int last_ring = 0;
    for (const Vec2& p : pattern) {
      const double j = p.y() / (0.5 * std::sqrt(3.0) * s);
      const double i = (p.x() - 0.5 * s * j) / s;
      ASSERT_NEAR(i, std::round(i), 1e-9);
      ASSERT_NEAR(j, std::round(j), 1e-9);
      const int ring = static_cast<int>(
          std::max({std::abs(std::round(i)), std::abs(std::round(j)), std::abs(std::round(i) + std::round(j))}));
      EXPECT_GE(ring, last_ring);
      last_ring = ring;
    }
    // Each kept cell meets the region, so each point lies within the cover radius of it.
    const auto dense = points_of_ellipse(c.a, c.b, c.angle, 40000, seed++);
    for (const Vec2& p : pattern) {
      double nearest = std::numeric_limits<double>::infinity();
      for (const Vec2& x : dense) nearest = std::min(nearest, (x - p).norm());
      EXPECT_LE(nearest, c.cover + 0.02) << "a probe point far from the region: " << p.transpose();
    }
    // Cells are disjoint hexagons of area 3 sqrt(3)/2 cover^2 inside the region grown by
    // 2 cover (Steiner: area pi a b + perimeter r + pi r^2, perimeter <= 2 pi a).
    const double r = 2.0 * c.cover;
    const double grown = kPi * c.a * c.b + 2.0 * kPi * c.a * r + kPi * r * r;
    EXPECT_LE(static_cast<double>(pattern.size()), grown / (1.5 * std::sqrt(3.0) * c.cover * c.cover));
  }
}

TEST(ProbePattern, RefusesABadCoverRadiusOrCovariance) {
  EXPECT_THROW(probe_pattern(Mat3::Identity(), 0.0), InputError);
  EXPECT_THROW(probe_pattern(Mat3::Identity(), std::nan("")), InputError);
  Mat3 bad = Mat3::Identity();
  bad(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(probe_pattern(bad, 0.5), InputError);
}

}  // namespace
}  // namespace sarloc::avalanche
