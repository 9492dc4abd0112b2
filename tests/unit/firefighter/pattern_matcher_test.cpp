// Pattern comparison (seed 004 section IV-D, Algorithm 1): eq. (1), resampling, and ICP finding
// a walked stretch of a search pattern wherever it was rotated and moved to.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "sarloc/core/firefighter/pattern_matcher.hpp"
#include "test_buildings.hpp"

namespace sarloc::firefighter {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(PatternMatcher, PrincipalRotationUndoesARotatedRectilinearWalk) {
  const std::vector<Vec2> walk = {{0, 0}, {4, 0}, {4, 3}, {1, 3}, {1, 5}};
  for (double angle : {0.0, 0.3, -0.6, 1.2}) {
    std::vector<Vec2> rotated;
    for (const Vec2& p : walk) rotated.push_back(Eigen::Rotation2Dd(angle) * p);
    const double phi = PatternMatcher::principal_rotation(rotated);
    // Any multiple of 90 deg is as good: compare modulo pi/2.
    const double residual = std::remainder(angle + phi, 0.5 * kPi);
    EXPECT_NEAR(residual, 0.0, 0.01) << "angle " << angle;
  }
}

TEST(PatternMatcher, ResampleKeepsTheEndsAndTheSpacing) {
  const auto r = PatternMatcher::resample({{0, 0}, {1.2, 0}, {1.2, 1.3}}, 0.5);
  EXPECT_EQ(r.front(), Vec2(0, 0));
  EXPECT_EQ(r.back(), Vec2(1.2, 1.3));
  for (std::size_t k = 1; k + 1 < r.size(); ++k) EXPECT_LE((r[k] - r[k - 1]).norm(), 0.5 + 1e-9);
  EXPECT_EQ(r.size(), 6U);  // 2.5 m: 0, 0.5, ..., 2.5
}

TEST(PatternMatcher, FindsAWalkedStretchOfThePatternWhereverItWasMoved) {
  const FloorPlan plan = test::building("house-125");
  const PatternGridConfig grid;
  const auto sequences = extract_node_sequences(plan, grid);
  const PatternMatcher matcher(sequences, grid, PatternMatchConfig{});
  const auto& nodes = sequences.front().nodes;
  std::mt19937_64 rng(4);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (std::size_t start : {0UL, 17UL, 40UL, 71UL}) {
    // 20 m of the right-hand search, in an odometry frame rotated and moved, with noise.
    const Eigen::Rotation2Dd R(0.9);
    std::vector<Vec2> trajectory;
    for (std::size_t k = 0; k <= 20; ++k) {
      const Vec2 p = nodes[(start + k) % nodes.size()];
      trajectory.push_back(R * p + Vec2(30, -12) + Vec2(noise(rng), noise(rng)));
    }
    const auto obs = matcher.compare(trajectory);
    ASSERT_EQ(obs.size(), 2 * matcher.window_count());
    const auto best = std::min_element(obs.begin(), obs.end(),
                                       [](const auto& a, const auto& b) { return a.rmse < b.rmse; });
    const Vec2 now = nodes[(start + 20) % nodes.size()];
    EXPECT_LT(best->rmse, 0.15) << "start " << start;
    EXPECT_LT((best->position - now).norm(), 1e-9) << "start " << start;
    EXPECT_LT((best->fitted_position - now).norm(), 0.2) << "start " << start;
    EXPECT_NEAR(std::remainder(best->frame_heading + 0.9, 2 * kPi), 0.0, 0.05) << "the odometry frame's heading";
  }
}

}  // namespace
}  // namespace sarloc::firefighter
