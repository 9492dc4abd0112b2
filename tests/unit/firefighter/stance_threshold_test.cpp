// The adaptive stance threshold: below its floor always a stance; above it, halfway in log T
// between the recent stance and swing levels, with hysteresis.
#include "sarloc/core/firefighter/stance_threshold.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::firefighter {
namespace {

// A gait at 100 Hz: stance 0.3 s at T = stance_t, swing 0.7 s at T = swing_t.
int stances_counted(StanceThreshold& detector, double stance_t, double swing_t, int cycles) {
  int phases = 0;
  bool was = false;
  for (int c = 0; c < cycles; ++c)
    for (int k = 0; k < 100; ++k) {
      const bool in = detector.push(k < 30 ? stance_t : swing_t, 100.0);
      if (in && !was) ++phases;
      was = in;
    }
  return phases;
}

TEST(StanceThreshold, AStanceAboveTheFloorIsFoundFromTheGaitItself) {
  StanceThreshold fixed_floor_only([] {
    StanceThresholdConfig c;
    c.ceiling = c.floor;  // adapted no higher than the floor: a fixed threshold
    return c;
  }());
  EXPECT_EQ(stances_counted(fixed_floor_only, 5e4, 5e6, 10), 0) << "a roll-through stance above 1e4 is missed";
  StanceThreshold adaptive{StanceThresholdConfig{}};
  EXPECT_GE(stances_counted(adaptive, 5e4, 5e6, 10), 9);
  EXPECT_NEAR(std::log10(adaptive.threshold()), 0.5 * (std::log10(5e4) + std::log10(5e6)), 0.1);
}

TEST(StanceThreshold, BelowTheFloorIsAlwaysAStanceAndHysteresisHoldsNoise) {
  StanceThreshold detector{StanceThresholdConfig{}};
  for (int k = 0; k < 500; ++k) EXPECT_TRUE(detector.push(k % 2 == 0 ? 10.0 : 9e3, 100.0));
  // A stance flickering just above the middle stays a stance (hysteresis), a swing leaves it.
  stances_counted(detector, 1e3, 1e7, 5);
  const double mid = std::log10(detector.threshold());
  EXPECT_TRUE(detector.push(1e3, 100.0));
  EXPECT_TRUE(detector.push(std::pow(10.0, mid + 0.1), 100.0));
  EXPECT_FALSE(detector.push(1e7, 100.0));
}

TEST(StanceThreshold, ItsConfigIsCheckedNamingTheKey) {
  StanceThresholdConfig c;
  c.swing_quantile = 0.01;
  try {
    c.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("swing_quantile"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sarloc::firefighter
