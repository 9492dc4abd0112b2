// StallDetector: the patience rule behind the adaptive end of the search.
#include "sarloc/core/avalanche/stall_detector.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {

// A radius that no longer shrinks is stalled exactly window_steps steps after its best.
TEST(StallDetector, AConstantRadiusStallsAfterTheWindow) {
  StallDetector stall(10, 0.05);
  EXPECT_FALSE(stall.add(0.5));  // the first radius is the best so far
  for (int k = 1; k < 10; ++k) EXPECT_FALSE(stall.add(0.5)) << "step " << k;
  EXPECT_TRUE(stall.add(0.5));
  EXPECT_TRUE(stall.stalled());
  ASSERT_TRUE(stall.best().has_value());
  EXPECT_DOUBLE_EQ(*stall.best(), 0.5);
}

// The plateau of a fine search: the radius jitters by a few per cent around its floor (as in
// the stalled trials of issue 11, 0.43-0.52 m). Records become rare, so it stalls.
TEST(StallDetector, ANoisyPlateauStalls) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-0.04, 0.04);
  StallDetector stall(10, 0.05);
  int steps = 0;
  while (!stall.add(0.47 * (1.0 + jitter(rng))) && steps < 1000) ++steps;
  // At most one more record is possible below the first value (the jitter spans < 2 x 5 %).
  EXPECT_LE(steps, 2 * 10 + 1);
}

// A search whose radius keeps shrinking by more than min_improvement per window is never
// stalled, however long it takes, even when no single step improves by that much.
TEST(StallDetector, AStillImprovingRadiusIsNeverStalled) {
  StallDetector stall(10, 0.05);
  double r = 2.0;
  for (int k = 0; k < 500; ++k, r *= 0.99) EXPECT_FALSE(stall.add(r)) << "step " << k;  // 1 % a step

  // Shrinking in jumps of 8 % every 9 steps, up to 2 % noise on top: still progress (each
  // jump undercuts the best of the previous plateau by more than 5 %).
  StallDetector stepwise(10, 0.05);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> up(0.0, 0.02);
  double floor = 1.0;
  for (int k = 0; k < 300; ++k) {
    if (k % 9 == 0) floor *= 0.92;
    EXPECT_FALSE(stepwise.add(floor * (1.0 + up(rng)))) << "step " << k;
  }
}

// ... but shrinking by less than min_improvement per window is a stall: 4 % every 9 steps
// reaches a record only every 18 steps.
TEST(StallDetector, ShrinkingSlowerThanTheThresholdStalls) {
  StallDetector stall(10, 0.05);
  double floor = 1.0;
  int k = 0;
  for (; k < 100; ++k) {
    if (k > 0 && k % 9 == 0) floor *= 0.96;
    if (stall.add(floor)) break;
  }
  EXPECT_EQ(k, 10);
}

TEST(StallDetector, ResetForgetsTheBestAndNonFiniteRadiiAreNoProgress) {
  StallDetector stall(3, 0.05);
  stall.add(1.0);
  stall.add(1.0);
  stall.reset();
  EXPECT_FALSE(stall.best().has_value());
  EXPECT_EQ(stall.steps_since_improvement(), 0);
  EXPECT_FALSE(stall.add(std::nan("")));
  EXPECT_FALSE(stall.best().has_value());
  EXPECT_FALSE(stall.add(5.0));
  EXPECT_EQ(stall.steps_since_improvement(), 0);
  EXPECT_THROW(StallDetector(0, 0.05), ConfigError);
  EXPECT_THROW(StallDetector(5, 1.0), ConfigError);
}

}  // namespace
}  // namespace sarloc::avalanche
