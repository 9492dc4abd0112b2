// Which sector's daemon serves a device where it stands (issue 64, item 4): the area it walked
// into, with a margin so that a rescuer walking along a border does not hand his filters back
// and forth at every step; outlines that are no simple polygon, or overlap, are refused.
#include "sarloc/core/incident/sector_areas.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::incident {
namespace {

std::vector<Vec2> box(double west, double east, double south, double north) {
  return {{west, south}, {east, south}, {east, north}, {west, north}};
}

SectorAreas two_sectors(double margin_m = 5.0) {
  return SectorAreas({{"west", box(-100, 0, -50, 50)}, {"east", box(0, 100, -50, 50)}}, margin_m, "sectors");
}

TEST(SectorAreas, ADeviceMovesOnlyOnceBeyondTheMarginOfItsSectorAndStaysBetweenAreas) {
  const SectorAreas areas = two_sectors();
  EXPECT_EQ(areas.sector_for("west", {-20.0, 0.0}), "west");
  EXPECT_EQ(areas.sector_for("west", {3.0, 0.0}), "west") << "3 m over the border: within the margin";
  EXPECT_EQ(areas.sector_for("west", {6.0, 0.0}), "east");
  EXPECT_EQ(areas.sector_for("east", {-3.0, 0.0}), "east") << "the way back has the same margin";
  EXPECT_EQ(areas.sector_for("east", {-6.0, 0.0}), "west");
  EXPECT_EQ(areas.sector_for("east", {300.0, 0.0}), "east") << "beyond every area: stays where it was";
  EXPECT_EQ(areas.sector_for("", {-20.0, 0.0}), "west") << "a device of no sector joins the area it is in";
  EXPECT_EQ(areas.sector_for("west", {std::numeric_limits<double>::quiet_NaN(), 0.0}), "west");
  // Walking along the border, the GNSS noise across it never moves him.
  std::string sector = "west";
  int moves = 0;
  for (int k = 0; k < 100; ++k) {
    const std::string next = areas.sector_for(sector, {(k % 2 == 0 ? 4.0 : -4.0), -40.0 + k});
    moves += next != sector ? 1 : 0;
    sector = next;
  }
  EXPECT_EQ(moves, 0);
  EXPECT_EQ(two_sectors(0.0).sector_for("west", {0.5, 0.0}), "east") << "no margin: over the border is the other side";
}

TEST(SectorAreas, OutlinesThatAreNoSimplePolygonOrOverlapAreRefusedNamingTheSector) {
  const auto refused = [](std::vector<SectorAreas::Area> areas, double margin, const std::string& expected) {
    try {
      SectorAreas(std::move(areas), margin, "sectors");
      ADD_FAILURE() << "expected a refusal mentioning '" << expected << "'";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  refused({{"west", box(-100, 0, -50, 50)}, {"east", box(-10, 100, -50, 50)}}, 5.0,
          "the areas of 'west' and 'east' overlap by 1000");
  refused({{"west", {{0, 0}, {10, 10}, {10, 0}, {0, 10}}}}, 5.0, "sectors[west].area: not a simple polygon");
  refused({{"west", {{0, 0}, {10, 0}}}}, 5.0, "sectors[west].area: 2 vertices");
  refused({{"west", box(-100, 0, -50, 50)}}, -1.0, "margin = -1");
}

}  // namespace
}  // namespace sarloc::incident
