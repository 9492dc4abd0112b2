// A mission's sector areas (issue 64, item 4): read from WGS-84 into the incident frame; with
// them every sector's daemon admits every rescuer (any may walk in) and keeps the journals a
// hand-over needs, unless the file says otherwise; without them nothing changes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "sarloc/app/mission_config.hpp"

namespace sarloc::app {
namespace {

const std::filesystem::path kMissions = std::filesystem::path(SARLOC_SOURCE_DIR) / "tests/integration/mission";

bool lists(const dds::CoreNodeConfig& core, const std::string& id) {
  return std::find(core.roster.listed.begin(), core.roster.listed.end(), id) != core.roster.listed.end();
}

TEST(SectorConfig, AreasAreReadIntoTheIncidentFrameAndEveryDaemonTakesEveryRescuer) {
  const auto mission = load_mission_config((kMissions / "sector-move.yaml").string());
  ASSERT_EQ(mission.sector_areas.areas().size(), 2U);
  EXPECT_DOUBLE_EQ(mission.sector_areas.margin_m(), 5.0);
  const auto& west = mission.sector_areas.areas()[0];
  EXPECT_EQ(west.sector, "west");
  double min_east = 1e9, max_east = -1e9;
  for (const auto& v : west.outline) {
    min_east = std::min(min_east, v.x());
    max_east = std::max(max_east, v.x());
  }
  EXPECT_NEAR(min_east, -150.0, 0.5);
  EXPECT_NEAR(max_east, 0.0, 0.05);
  EXPECT_EQ(mission.sector_areas.sector_for("west", {20.0, 40.0}), "east");
  for (const char* sector : {"west", "east"}) {
    const auto core = mission.core_config(sector);
    EXPECT_TRUE(lists(core, "r1")) << sector;
    EXPECT_EQ(core.handover_journal_entries, kHandoverJournalWithAreas) << sector;
  }

  const auto without = load_mission_config((kMissions / "sectors.yaml").string());
  EXPECT_TRUE(without.sector_areas.empty());
  EXPECT_EQ(without.core_config("east").handover_journal_entries, 0U);
  EXPECT_FALSE(lists(without.core_config("east"), "west-1"));
}

}  // namespace
}  // namespace sarloc::app
