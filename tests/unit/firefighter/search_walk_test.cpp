// The simulated directional searches: they never pass through a wall or furniture, they last
// as asked, the second member follows the first, and in the two-storey office they climb.
#include <gtest/gtest.h>

#include <random>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/firefighter/search_walk.hpp"
#include "sarloc/core/firefighter/wall_index.hpp"
#include "test_buildings.hpp"

namespace sarloc::firefighter {
namespace {

void expect_never_through_a_wall(const FloorPlan& plan, const std::vector<Footfall>& feet, const std::string& what) {
  std::vector<WallIndex> world;
  for (std::size_t f = 0; f < plan.floors.size(); ++f) world.emplace_back(plan.solid_walls(f, WallSet::kWorld));
  for (std::size_t k = 1; k < feet.size(); ++k) {
    if (feet[k].floor != feet[k - 1].floor) continue;  // on the stairs' midline
    ASSERT_FALSE(world[feet[k].floor].crosses(feet[k - 1].position.head<2>(), feet[k].position.head<2>()))
        << what << " footfall " << k << " at " << feet[k].position.transpose();
  }
}

TEST(SearchWalk, NeverWalksThroughAWallAndLastsTheSearchTime) {
  for (const char* name : {"house-125", "office-253", "warehouse-1040"}) {
    const FloorPlan plan = test::building(name);
    for (std::uint64_t seed : {1, 2, 3, 4}) {
      std::mt19937_64 rng(seed);
      const SearchWalk walk = generate_search_walk(plan, SearchWalkConfig{}, seed % 2 ? Hand::kLeft : Hand::kRight, rng);
      expect_never_through_a_wall(plan, walk.leader, std::string(name) + " leader");
      expect_never_through_a_wall(plan, walk.follower, std::string(name) + " follower");
      EXPECT_GE(walk.leader.back().t_land, 300.0) << name;
      EXPECT_GT(walk.distance_m, 40.0) << name << " seed " << seed << ": a search moves on";
      EXPECT_EQ(walk.leader.size(), walk.follower.size());
      EXPECT_NEAR(walk.follower.back().t_land - walk.leader.back().t_land, SearchWalkConfig{}.follower_delay_s, 1e-9);
    }
  }
}

// The simulated device's first fix and the live filter's known start: the entry, its floor,
// turned to the wall the search follows (a right-hand search turns right from walking in).
TEST(SearchWalk, TheEntryStanceIsTheDoorTurnedToTheFollowedWall) {
  const FloorPlan plan = test::building("house-125");
  const auto right = entry_stance(plan, "front", Hand::kRight);
  ASSERT_TRUE(right);
  EXPECT_NEAR((right->position - Vec2(0.5, 5.0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(right->floor, 0U);
  EXPECT_NEAR(right->heading_rad, -0.5 * kPi, 1e-12) << "walking in east, the right hand is south";
  EXPECT_NEAR(entry_stance(plan, "front", Hand::kLeft)->heading_rad, 0.5 * kPi, 1e-12);
  EXPECT_FALSE(entry_stance(plan, "back", Hand::kRight));
}

TEST(SearchWalk, ClimbsTheStairsOfTheTwoStoreyOffice) {
  const FloorPlan plan = test::building("office-253");
  int climbed = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    std::mt19937_64 rng(seed);
    SearchWalkConfig config;
    config.duration_s = 600.0;
    const SearchWalk walk = generate_search_walk(plan, config, seed % 2 ? Hand::kLeft : Hand::kRight, rng);
    bool upper = false;
    for (const Footfall& f : walk.leader) {
      if (f.floor == 1) {
        upper = true;
        EXPECT_GT(f.position.z(), 1.4) << "on the upper floor, above the flight's midpoint";
      }
    }
    climbed += upper ? 1 : 0;
  }
  EXPECT_GE(climbed, 3) << "most directional searches of the office reach the upper floor in 10 minutes";
}

}  // namespace
}  // namespace sarloc::firefighter
