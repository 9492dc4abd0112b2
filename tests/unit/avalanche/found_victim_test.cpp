#include "sarloc/core/avalanche/found_victim.hpp"

#include <gtest/gtest.h>

#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche {
namespace {

const std::vector<Vec3> kVictims = {Vec3(0.0, 0.0, -1.0), Vec3(0.3, 0.0, -1.0), Vec3(3.4, 0.0, -1.2)};

// Two victims 0.3 m apart, each found by its own signal, are two victims found.
TEST(VictimOfFound, TheSignalsOwnTransmitterWithinReachIsTheOneFound) {
  EXPECT_EQ(victim_of_found(Vec3(0.2, 0.0, -1.0), 0.6, kVictims, 0), 0U);
  EXPECT_EQ(victim_of_found(Vec3(0.2, 0.0, -1.0), 0.6, kVictims, 1), 1U);
}

// Live: a signal whose first pulses were victim C's followed victim A and found it 0.08 m off.
// Scored by its first pulse it was a FOUND 3.4 m off C; it found A.
TEST(VictimOfFound, AFoundOfAnotherVictimThanTheSignalsOwnNamesTheNearestWithinReach) {
  EXPECT_EQ(victim_of_found(Vec3(3.35, 0.05, -1.2), 0.7, kVictims, 0), 2U);
  EXPECT_EQ(victim_of_found(Vec3(0.25, 0.0, -1.0), 0.7, kVictims, std::nullopt), 1U);
}

TEST(VictimOfFound, AFoundNearNoVictimIsAGhost) {
  EXPECT_FALSE(victim_of_found(Vec3(1.8, 0.0, -1.0), 0.7, kVictims, 0).has_value());
  EXPECT_FALSE(victim_of_found(Vec3(0.0, 0.0, -1.0), 0.5, {}, std::nullopt).has_value());
  // An index the truth does not hold is no victim.
  EXPECT_EQ(victim_of_found(Vec3(0.0, 0.0, -1.0), 0.5, kVictims, 7), 0U);
}

TEST(VictimOfFound, ReachIsTheStatedRadiusPlusTheProbesMargin) {
  const Mat3 cov = Vec3(0.01, 0.02, 0.04).asDiagonal();
  EXPECT_DOUBLE_EQ(found_reach(cov), radius95_3d(cov) + kFalseFoundMarginM);
}

}  // namespace
}  // namespace sarloc::avalanche
