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

// A covariance whose 95 % 3-D radius is `radius`.
Mat3 stated(double radius) {
  const Mat3 unit = Mat3::Identity();
  return unit * (radius / radius95_3d(unit)) * (radius / radius95_3d(unit));
}

// 4 victims seed 6 trial 36: victims 0.31 m apart; signal A found victim 0 0.01 m off; signal B,
// fed both transmitters' pulses (most of them victim 0's), found the spot 0.10 m from victim 1
// inside its 0.15 m radius, 0.29 m from victim 0. Both victims are found, neither twice.
TEST(MatchFounds, AFoundInsideItsRadiusOfAVictimNoOtherFoundNamesFindsIt) {
  const std::vector<Vec3> victims = {Vec3(-41.86, -19.55, -0.43), Vec3(-41.62, -19.36, -0.64)};
  const FoundClaim a{Vec3(-41.87, -19.56, -0.48), stated(0.14), 0};
  const FoundClaim b{Vec3(-41.69, -19.36, -0.57), stated(0.15), 0};
  ASSERT_GT((victims[0] - b.position).norm(), 0.15);  // outside b's radius: b names victim 0 alone
  EXPECT_EQ(victim_of_found(b.position, found_reach(b.covariance), victims, b.own), 0U);
  for (const auto& order : {std::vector<FoundClaim>{a, b}, std::vector<FoundClaim>{b, a}}) {
    const FoundMatching m = match_founds(order, victims);
    EXPECT_EQ(m.found, 2U);
    EXPECT_EQ(m.duplicates, 0U);
    EXPECT_EQ(m.ghosts, 0U);
  }
}

// A repeat stays a repeat: two FOUNDs on one victim, the other victim 0.5 m away, within reach
// (radius + margin) but outside both radii.
TEST(MatchFounds, TwoFoundsOfOneVictimAreOneVictimTwiceThoughAnotherIsWithinReach) {
  const std::vector<Vec3> victims = {Vec3(0.0, 0.0, -1.0), Vec3(0.5, 0.0, -1.0)};
  const std::vector<FoundClaim> founds = {{Vec3(0.02, 0.0, -1.0), stated(0.15), 0},
                                          {Vec3(-0.05, 0.0, -1.0), stated(0.15), 0}};
  const FoundMatching m = match_founds(founds, victims);
  EXPECT_EQ(m.found, 1U);
  EXPECT_EQ(m.duplicates, 1U);
  EXPECT_EQ(m.ghosts, 0U);
  EXPECT_EQ(m.victim[0], 0U);
  EXPECT_FALSE(m.victim[1].has_value());
}

TEST(MatchFounds, AFoundNearNoVictimIsAGhostAndEachVictimCountsOnce) {
  const std::vector<FoundClaim> founds = {{Vec3(0.0, 0.0, -1.0), stated(0.2), 0},
                                          {Vec3(3.4, 0.0, -1.2), stated(0.2), std::nullopt},
                                          {Vec3(8.0, 0.0, -1.0), stated(0.2), 1}};
  const FoundMatching m = match_founds(founds, kVictims);
  EXPECT_EQ(m.found, 2U);
  EXPECT_EQ(m.ghosts, 1U);
  EXPECT_EQ(m.duplicates, 0U);
  EXPECT_EQ(m.victim[1], 2U);
}

}  // namespace
}  // namespace sarloc::avalanche
