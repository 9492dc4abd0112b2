// Pattern extraction (seed 004 section IV-C) on the shipped buildings.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tuple>
#include <vector>

#include "sarloc/core/firefighter/search_pattern.hpp"
#include "sarloc/core/firefighter/wall_index.hpp"
#include "test_buildings.hpp"

namespace sarloc::firefighter {
namespace {

TEST(SearchPattern, SequencesAreClosedUnitStepsThatNeverCrossAWall) {
  for (const char* name : {"house-125", "office-253", "warehouse-1040"}) {
    const FloorPlan plan = test::building(name);
    const auto sequences = extract_node_sequences(plan, PatternGridConfig{});
    ASSERT_FALSE(sequences.empty()) << name;
    for (const NodeSequence& seq : sequences) {
      const WallIndex walls(plan.solid_walls(seq.floor, WallSet::kNavigation));
      for (std::size_t k = 0; k < seq.nodes.size(); ++k) {
        const Vec2& a = seq.nodes[k];
        const Vec2& b = seq.nodes[(k + 1) % seq.nodes.size()];  // p_N is adjacent to p_1
        EXPECT_NEAR((b - a).norm(), 1.0, 1e-9) << name << " node " << k;
        EXPECT_FALSE(walls.crosses(a, b)) << name << " node " << k;
      }
    }
  }
}

TEST(SearchPattern, InnerWallsGetTheirOwnSequencesAndTheMainOneVisitsEveryRoom) {
  const FloorPlan plan = test::building("house-125");
  const auto sequences = extract_node_sequences(plan, PatternGridConfig{});
  std::size_t inner = 0;
  for (const auto& s : sequences) inner += s.around_inner_walls ? 1 : 0;
  EXPECT_EQ(inner, 2U) << "the kitchen island and the partition of room E";
  // The entry's right-hand sequence passes every room: a node in each room's interior.
  const std::vector<Vec2> rooms = {{2.5, 2.5}, {7.0, 2.0}, {10.75, 2.0}, {3.0, 8.0}, {9.25, 8.0}, {6.0, 5.0}};
  for (const Vec2& room : rooms) {
    bool visited = false;
    for (const Vec2& n : sequences.front().nodes) visited = visited || (n - room).cwiseAbs().maxCoeff() < 2.0;
    EXPECT_TRUE(visited) << room.transpose();
  }
}

// Each room of the house is entered and left by one door: the search may pass it by, going
// from the node before the room straight on to the node after it.
TEST(SearchPattern, EveryRoomOfTheHouseCanBePassedBy) {
  const FloorPlan plan = test::building("house-125");
  const auto sequences = extract_node_sequences(plan, PatternGridConfig{});
  const NodeSequence& main = sequences.front();
  ASSERT_FALSE(main.around_inner_walls);
  const WallIndex walls(plan.solid_walls(0, WallSet::kNavigation));
  const std::vector<Vec2> rooms = {{2.5, 2.5}, {7.0, 2.0}, {10.75, 2.0}, {3.0, 8.0}, {9.25, 8.0}};
  ASSERT_EQ(main.room_skips.size(), rooms.size());
  std::vector<bool> passed_by(rooms.size(), false);
  for (const RoomSkip& skip : main.room_skips) {
    ASSERT_LT(skip.from + 4, skip.to);
    ASSERT_LT(skip.to, main.nodes.size());
    const Vec2& a = main.nodes[skip.from];
    const Vec2& b = main.nodes[skip.to];
    EXPECT_NEAR((b - a).norm(), 1.0, 1e-9) << "a grid step";
    EXPECT_FALSE(walls.crosses(a, b));
    // The nodes left out are one room's: the corridor is y in [4, 6].
    for (std::size_t r = 0; r < rooms.size(); ++r) {
      bool all_in = true;
      for (std::size_t k = skip.from + 2; k + 1 < skip.to; ++k) {
        const Vec2& n = main.nodes[k];
        all_in = all_in && (n.y() < 4.0) == (rooms[r].y() < 4.0) && (n.y() < 4.0 || n.y() > 6.0) &&
                 std::abs(n.x() - rooms[r].x()) < 3.6;
      }
      passed_by[r] = passed_by[r] || all_in;
    }
  }
  for (std::size_t r = 0; r < rooms.size(); ++r) EXPECT_TRUE(passed_by[r]) << "room at " << rooms[r].transpose();
  PatternGridConfig none;
  none.room_skips = false;
  for (const auto& s : extract_node_sequences(plan, none)) EXPECT_TRUE(s.room_skips.empty());
}

TEST(SearchPattern, TwoEntriesOnOneLoopGiveItOnceSoNoWindowIsComparedTwice) {
  // The warehouse's south and west entries open on the same outer loop: one sequence, which
  // passes both entries.
  const FloorPlan warehouse = test::building("warehouse-1040");
  ASSERT_EQ(warehouse.entries.size(), 2U);
  const auto sequences = extract_node_sequences(warehouse, PatternGridConfig{});
  std::size_t from_entries = 0;
  for (const auto& s : sequences) from_entries += s.around_inner_walls ? 0 : 1;
  EXPECT_EQ(from_entries, 1U);
  for (const auto& entry : warehouse.entries) {
    double nearest = 1e9;
    for (const Vec2& n : sequences.front().nodes) nearest = std::min(nearest, (n - entry.position).norm());
    EXPECT_LT(nearest, 1.0) << entry.id;
  }
  // On every building, no 20 m window (21 nodes) of one floor appears twice.
  for (const char* name : {"house-125", "office-253", "warehouse-1040"}) {
    std::set<std::tuple<std::size_t, std::vector<std::pair<double, double>>>> windows;
    std::size_t total = 0;
    for (const auto& s : extract_node_sequences(test::building(name), PatternGridConfig{})) {
      const std::size_t n = s.nodes.size();
      if (n <= 20) continue;
      for (std::size_t eta = 0; eta < n; ++eta) {
        std::vector<std::pair<double, double>> w;
        for (std::size_t k = 0; k <= 20; ++k) w.emplace_back(s.nodes[(eta + k) % n].x(), s.nodes[(eta + k) % n].y());
        windows.emplace(s.floor, std::move(w));
        ++total;
      }
    }
    EXPECT_EQ(windows.size(), total) << name;
  }
}

TEST(SearchPattern, NavigableAreaMatchesTheBuildingsSize) {
  EXPECT_NEAR(navigable_grid(test::building("house-125"), PatternGridConfig{}).area_m2(0), 125.0, 12.0);
  const auto office = navigable_grid(test::building("office-253"), PatternGridConfig{});
  EXPECT_NEAR(office.area_m2(0) + office.area_m2(1), 253.0, 35.0);
  EXPECT_GE(navigable_grid(test::building("warehouse-1040"), PatternGridConfig{}).area_m2(0), 900.0);
}

}  // namespace
}  // namespace sarloc::firefighter
