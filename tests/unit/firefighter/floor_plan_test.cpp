// Floor plans: doors cut out of walls, entry doors closed, furniture only in the world, the
// stairs' rectangle, the wall index's queries. Malformed files: tests/config/invalid/building.
#include <gtest/gtest.h>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/firefighter/floor_plan.hpp"
#include "sarloc/core/firefighter/wall_index.hpp"
#include "test_buildings.hpp"

namespace sarloc::firefighter {
namespace {

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
  try {
    plan.validate();
    FAIL() << "a door off its wall validated";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("floors[ground].doors[door_a]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sarloc::firefighter
