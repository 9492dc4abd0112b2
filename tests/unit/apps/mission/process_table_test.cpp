// sarloc-mission's process table: which processes a mission has, and where --host may place
// them. (Starting, killing and stopping them: tests/integration/mission.)
#include <gtest/gtest.h>

#include <filesystem>

#include "process_table.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::app {
namespace {

const std::filesystem::path kMissions = std::filesystem::path(SARLOC_SOURCE_DIR) / "tests/integration/mission";

std::string placement_problem(const MissionConfig& mission, std::map<std::string, std::string> hosts,
                              const std::string& launcher) {
  ProcessTableConfig config;
  config.hosts = std::move(hosts);
  config.launcher = launcher;
  try {
    ProcessTable table(mission, config);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ProcessTable, EveryProcessOfAMissionHasAName) {
  const auto sectors = load_mission_config((kMissions / "sectors.yaml").string());
  EXPECT_EQ(ProcessTable::placeable_names(sectors),
            (std::set<std::string>{"core-west", "core-east", "command-1", "command-2", "rescuer-west-1",
                                   "rescuer-east-1"}));
  const auto mixed = load_mission_config((kMissions / "mixed.yaml").string());
  EXPECT_EQ(ProcessTable::placeable_names(mixed),
            (std::set<std::string>{"core", "command-1", "command-2", "rescuer-r1", "rescuer-r2", "rescuer-ff1",
                                   "rescuer-ff2"}));
  const auto single = load_mission_config((kMissions / "single_command.yaml").string());
  EXPECT_EQ(ProcessTable::placeable_names(single).count("command"), 1U);
  ProcessTable table(single, ProcessTableConfig{});
  EXPECT_EQ(table.command_name(1), "command");
}

TEST(ProcessTable, AHostPlacementNeedsALauncherAndAProcessOfThatName) {
  const auto mission = load_mission_config((kMissions / "mixed.yaml").string());
  EXPECT_EQ(placement_problem(mission, {}, ""), "");
  EXPECT_EQ(placement_problem(mission, {{"rescuer-r1", "h5"}}, "lan-exec"), "");
  EXPECT_EQ(placement_problem(mission, {{"rescuer-r1", "h5"}}, ""),
            "--host given without --launcher: nothing can start a process on a host");
  EXPECT_EQ(placement_problem(mission, {{"rescuer-r9", "h5"}}, "lan-exec"),
            "--host rescuer-r9=h5: no process 'rescuer-r9' in this mission");
  EXPECT_EQ(placement_problem(mission, {{"core", ""}}, "lan-exec"), "--host core=: empty host");
  EXPECT_EQ(ProcessTable::programs(true).back(), "sarloc-dashboard");
  EXPECT_EQ(ProcessTable::programs(false).size(), 4U);
}

}  // namespace
}  // namespace sarloc::app
