#include "sarloc/core/incident/responder_track.hpp"

#include <gtest/gtest.h>

namespace sarloc::incident {
namespace {

constexpr TimestampNs kSec = 1'000'000'000;

ReporterFix at(double x, double y, double sigma = 0.3, std::int32_t floor = 0) {
  ReporterFix f;
  f.antenna.position = Vec3(x, y, 1.0);
  f.antenna.covariance = sigma * sigma * Mat3::Identity();
  f.floor = floor;
  return f;
}

TEST(ResponderTrack, NearestFixWithinTheAge) {
  ResponderTrack t;
  EXPECT_FALSE(t.at(kSec, kSec / 2, 3 * kSec).has_value()) << "no fix at all";
  t.add(1 * kSec, at(0, 0));
  t.add(2 * kSec, at(1, 0));
  EXPECT_DOUBLE_EQ(t.at(2 * kSec, kSec / 2, 0)->antenna.position.x(), 1.0);
  EXPECT_DOUBLE_EQ(t.at(2 * kSec + kSec / 4, kSec / 2, 0)->antenna.position.x(), 1.0);
  EXPECT_DOUBLE_EQ(t.at(kSec + kSec / 4, kSec / 2, 0)->antenna.position.x(), 0.0);
  EXPECT_FALSE(t.at(3 * kSec, kSec / 2, 3 * kSec).has_value()) << "not bracketed: never extrapolated";
}

// The epoch's own fix lost (packet loss): the neighbours bracket it and are interpolated, with a
// wider covariance; too far apart, nothing.
TEST(ResponderTrack, LostFixIsInterpolatedBetweenCloseNeighbours) {
  ResponderTrack t;
  t.add(1 * kSec, at(0, 0));
  t.add(3 * kSec, at(2, 0, 0.4));  // the fix of 2 s is missing
  const auto p = t.at(2 * kSec, kSec / 2, 5 * kSec / 2);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->antenna.position.x(), 1.0, 1e-12);
  EXPECT_NEAR(p->antenna.covariance(0, 0), 0.16 + 0.25, 1e-12) << "the larger fix covariance + (2 m / 4)^2";
  EXPECT_NEAR(p->antenna.covariance(2, 2), 0.16, 1e-12) << "height: not widened";
  EXPECT_FALSE(t.at(2 * kSec, kSec / 2, kSec).has_value()) << "gap of 2 s over the 1 s limit";
}

TEST(ResponderTrack, OutOfOrderAndDuplicateFixesAndCapacity) {
  ResponderTrack t(3);
  t.add(3 * kSec, at(3, 0));
  t.add(1 * kSec, at(1, 0));  // late arrival goes in its place
  t.add(2 * kSec, at(2, 0));
  t.add(2 * kSec, at(2.5, 0));  // same stamp: replaces
  EXPECT_DOUBLE_EQ(t.at(2 * kSec, 0, 0)->antenna.position.x(), 2.5);
  t.add(4 * kSec, at(4, 0));  // capacity 3: the oldest goes
  EXPECT_FALSE(t.at(1 * kSec, 0, 0).has_value());
  EXPECT_DOUBLE_EQ(t.at(4 * kSec, 0, 0)->antenna.position.x(), 4.0);
}

TEST(ResponderTrack, NeverInterpolatesAcrossFloors) {
  ResponderTrack t;
  t.add(1 * kSec, at(0, 0, 0.3, 1));
  t.add(3 * kSec, at(0, 0, 0.3, 2));  // took the stairs
  EXPECT_FALSE(t.at(2 * kSec, kSec / 2, 5 * kSec).has_value());
  const auto nearest = t.at(3 * kSec, kSec / 2, 0);
  ASSERT_TRUE(nearest.has_value());
  EXPECT_EQ(nearest->floor, 2);
}

}  // namespace
}  // namespace sarloc::incident
