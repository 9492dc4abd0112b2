// Floor plans: doors cut out of walls, entry doors closed, furniture only in the world, the
// stairs' rectangle, the wall index's queries. Malformed files: tests/config/invalid/building.
#include "sarloc/core/firefighter/floor_plan.hpp"

#include <gtest/gtest.h>

#include <boost/geometry.hpp>
#include <cmath>
#include <random>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/firefighter/wall_index.hpp"
#include "support/config_messages.hpp"
#include "test_buildings.hpp"

namespace sarloc::firefighter {
namespace {

// The reference: Boost.Geometry's segment-segment test, one wall at a time.
bool segments_touch(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  namespace bg = boost::geometry;
  using P = bg::model::point<double, 2, bg::cs::cartesian>;
  using S = bg::model::segment<P>;
  return bg::intersects(S(P(a.x(), a.y()), P(b.x(), b.y())), S(P(c.x(), c.y()), P(d.x(), d.y())));
}

double total_length(const std::vector<Segment>& s) {
  double d = 0.0;
  for (const auto& x : s) d += x.length();
  return d;
}

TEST(FloorPlan, DoorsAreCutOutOfTheirWallsAndEntryDoorsStayClosed) {
  const FloorPlan plan = test::building("house-125");
  const auto nav = plan.solid_walls(0, WallSet::kNavigation);
  const auto world = plan.solid_walls(0, WallSet::kWorld);
  double walls = 0.0, doors = 0.0;
  for (const Wall& w : plan.floors[0].walls) walls += (w.b - w.a).norm();
  for (const Door& d : plan.floors[0].doors) doors += d.id == "front" ? 0.0 : d.width_m;
  EXPECT_NEAR(total_length(nav), walls - doors, 1e-9);
  EXPECT_GT(world.size(), nav.size()) << "furniture is part of the world";
  const WallIndex index(nav);
  EXPECT_FALSE(index.crosses({3.5, 3.5}, {3.5, 4.5})) << "through door_a";
  EXPECT_TRUE(index.crosses({1.0, 3.5}, {1.0, 4.5})) << "through the corridor wall";
  EXPECT_TRUE(index.crosses({0.5, 5.0}, {-0.5, 5.0})) << "out of the closed entry door";
}

TEST(FloorPlan, WallIndexMeasuresRaysAndClearance) {
  const WallIndex index({{{0, 0}, {10, 0}}, {{10, 0}, {10, 10}}});
  EXPECT_NEAR(index.ray({5, 5}, -0.5 * 3.14159265358979, 20.0), 5.0, 1e-9);
  EXPECT_NEAR(index.ray({5, 5}, 0.0, 20.0), 5.0, 1e-9);
  EXPECT_NEAR(index.ray({5, 5}, 0.5 * 3.14159265358979, 20.0), 20.0, 1e-9) << "nothing north";
  EXPECT_NEAR(index.clearance({9, 5}), 1.0, 1e-9);
  EXPECT_NEAR(index.clearance({12, -1}), std::hypot(2.0, 1.0), 1e-9);
}

// The grid of clearances lets short moves skip the tree; it must never change an answer. Moves
// of every length up to 3 m from anywhere on and around the warehouse's floor (furniture and
// all), short ones grazing walls included, against Boost's segment test over every wall.
TEST(FloorPlan, WallIndexCrossingsAgreeWithEveryWallTestedOneByOne) {
  const FloorPlan plan = test::building("warehouse-1040");
  const auto walls = plan.solid_walls(0, WallSet::kWorld);
  const WallIndex index(walls);
  Vec2 lo = walls.front().a, hi = lo;
  for (const Segment& w : walls) {
    lo = lo.cwiseMin(w.a).cwiseMin(w.b);
    hi = hi.cwiseMax(w.a).cwiseMax(w.b);
  }
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ux(lo.x() - 3.0, hi.x() + 3.0), uy(lo.y() - 3.0, hi.y() + 3.0);
  std::uniform_real_distribution<double> length(0.0, 3.0), angle(-3.14159265358979, 3.14159265358979), unit(0.0, 1.0);
  int crossing = 0;
  for (int k = 0; k < 100000; ++k) {
    Vec2 a(ux(rng), uy(rng));
    if (k % 4 == 0) {  // start right beside a wall
      const Segment& w = walls[static_cast<std::size_t>(k / 4) % walls.size()];
      a = w.a + unit(rng) * (w.b - w.a) + 0.02 * Vec2(unit(rng) - 0.5, unit(rng) - 0.5);
    }
    const double l = k % 2 ? 0.05 * length(rng) : length(rng), h = angle(rng);
    const Vec2 b = a + l * Vec2(std::cos(h), std::sin(h));
    bool expected = false;
    for (const Segment& w : walls) expected = expected || segments_touch(a, b, w.a, w.b);
    ASSERT_EQ(index.crosses(a, b), expected) << "move " << a.transpose() << " -> " << b.transpose();
    crossing += expected;
  }
  EXPECT_GT(crossing, 5000) << "the moves must test crossings, not only open space";
}

TEST(FloorPlan, StairsProgressRunsFromBottomToTopInsideTheirRectangle) {
  const FloorPlan plan = test::building("office-253");
  ASSERT_EQ(plan.stairs.size(), 1U);
  const Stairs& s = plan.stairs[0];
  EXPECT_NEAR(*s.progress({10.75, 3.5}), 0.0, 1e-9);
  EXPECT_NEAR(*s.progress({10.75, 6.0}), 0.5, 1e-9);
  EXPECT_FALSE(s.progress({9.5, 6.0}).has_value()) << "beside the flight";
  EXPECT_EQ(plan.stairs_of(0).size(), 1U);
  EXPECT_EQ(plan.stairs_of(1).size(), 1U);
}

TEST(FloorPlan, ValidateNamesTheElement) {
  FloorPlan plan = test::building("house-125");
  plan.floors[0].doors[1].center.x() = 40.0;
  EXPECT_NE(sarloc::test::validation_error(plan).find("floors[ground].doors[door_a]"), std::string::npos)
      << sarloc::test::validation_error(plan);
}

}  // namespace
}  // namespace sarloc::firefighter
