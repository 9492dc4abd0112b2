// A real boot IMU recording through the live system: sarloc-rescuer plays x-io's short walk
// (../shared/data/imu, read by config/imu/xio-ngimu.yaml) as firefighter ff1 in house-125, and
// sarloc-core's map-aided filter takes every odometry step of it and answers with positions.
// Before issue 62 the device never aligned on such a file, and the daemon refused 7 of its 80
// steps as absurd motion (a boot's 0.5 s can hold 1.29 m of a walk).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "mission_runs.hpp"
#include "support/dds_test_domains.hpp"

namespace sarloc::test {
namespace {

TEST(RecordedBoot, ARealRecordingDrivesAFirefighterThroughTheDaemon) {
  const fs::path recording = fs::path(SARLOC_SOURCE_DIR) / "../shared/data/imu/xio-gait-tracking/short_walk.csv";
  if (!fs::exists(recording)) GTEST_SKIP() << recording << " is not on this machine";
  const fs::path dir = fs::temp_directory_path() / "sarloc-recorded-boot";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string bin = SARLOC_BIN_DIR, mission = std::string(SARLOC_MISSION_DIR) + "/firefighters.yaml";
  const std::string domain = std::to_string(kDomainRecordedBoot);
  // The device's mission clock starts a second from now, 4x fast (the walk is 41.6 s).
  const auto epoch = std::chrono::duration_cast<std::chrono::nanoseconds>(
                         std::chrono::system_clock::now().time_since_epoch() + std::chrono::seconds(1))
                         .count();
  const std::string script = "cd " + dir.string() + " && " + bin + "/sarloc-core -c " + mission + " --domain " +
                             domain + " > core.log 2>&1 & CORE=$!; " + bin + "/sarloc-rescuer -c " + mission +
                             " --id ff1 --source " + recording.string() + " --imu-source " + SARLOC_SOURCE_DIR +
                             "/config/imu/xio-ngimu.yaml --domain " + domain + " --epoch-ns " + std::to_string(epoch) +
                             " --speedup 4 --quiet --summary " + (dir / "ff1.json").string() + " > " +
                             (dir / "ff1.log").string() + " 2>&1; RC=$?; kill $CORE; wait $CORE; exit $RC";
  const int status = std::system(("sh -c '" + script + "'").c_str());
  ASSERT_EQ(status, 0) << file_text(dir / "ff1.log") << file_text(dir / "core.log");
  std::ifstream in(dir / "ff1.json");
  ASSERT_TRUE(in) << "no device summary; " << file_text(dir / "ff1.log");
  const auto summary = nlohmann::json::parse(in);
  // The INS walked the loop (22.3 m by sarloc-eval ins) and the daemon answered nearly every
  // 0.5 s step (80 of them) with a map-aided position.
  EXPECT_NEAR(summary["distance_walked_m"].get<double>(), 22.5, 2.5) << summary.dump();
  EXPECT_GE(summary["fixes"].get<int>(), 60) << summary.dump();
  EXPECT_LT(summary["dead_reckoning_s"].get<double>(), 5.0) << summary.dump();
  const std::string core = file_text(dir / "core.log");
  EXPECT_NE(core.find("new responder 'ff1' (firefighter)"), std::string::npos) << core;
  EXPECT_NE(core.find(" 0 rejected"), std::string::npos) << core;
  EXPECT_NE(file_text(dir / "ff1.log").find("after 80 odometry steps (0 malformed rows skipped)"), std::string::npos)
      << file_text(dir / "ff1.log");
}

// The same recording as ff1 of a whole mission (recorded-boot.yaml names it), beside a simulated
// ff2: sarloc-mission starts the device on it, the summary has it walked and placed (no truth,
// so no RMSE), and the recording and its report hold its track.
TEST(RecordedBoot, ARecordedFirefighterGoesThroughAWholeMissionIntoItsRecordingAndReport) {
  const fs::path recording = fs::path(SARLOC_SOURCE_DIR) / "../shared/data/imu/xio-gait-tracking/short_walk.csv";
  if (!fs::exists(recording)) GTEST_SKIP() << recording << " is not on this machine";
  const MissionRun run = run_mission("recorded-boot.yaml", kDomainRecordedBootMission);
  ASSERT_FALSE(run.summary.is_null()) << run_report(run);
  EXPECT_EQ(run.exit_code, 0) << run_report(run);
  std::map<std::string, json> firefighters;
  for (const auto& f : run.summary["firefighters"]) firefighters[f["responder_id"]] = f;
  ASSERT_EQ(firefighters.size(), 2u) << run.summary.dump();
  const json& ff1 = firefighters["ff1"];
  EXPECT_NEAR(ff1["distance_walked_m"].get<double>(), 22.5, 2.5) << ff1.dump();
  EXPECT_GE(ff1["fixes"].get<int>(), 60) << ff1.dump();
  EXPECT_FALSE(ff1.contains("rmse_after_convergence_m")) << "a recording has no truth in the plan: " << ff1.dump();
  EXPECT_TRUE(firefighters["ff2"].contains("rmse_after_convergence_m")) << firefighters["ff2"].dump();

  ASSERT_TRUE(run.summary.contains("recording")) << run_report(run);
  const fs::path html = run.run_dir / "report.html";
  const int reported =
      std::system((std::string(SARLOC_BIN_DIR) + "/sarloc-report '" + run.summary["recording"].get<std::string>() +
                   "' -o " + html.string() + " > " + (run.run_dir / "report.out").string() + " 2>&1")
                      .c_str());
  ASSERT_EQ(WEXITSTATUS(reported), 0) << file_text(run.run_dir / "report.out");
  const std::string page = file_text(html);
  EXPECT_NE(page.find("Building, floor 0"), std::string::npos);
  EXPECT_NE(page.find(">ff1</text>"), std::string::npos) << "ff1's track is labelled on the building map";
  // The responders table: ff1, its team, its role and how many positions the recording holds.
  const auto row = page.find("<td>ff1</td><td>alpha</td><td>firefighter</td><td>");
  ASSERT_NE(row, std::string::npos);
  EXPECT_GE(std::stoi(page.substr(row + std::string("<td>ff1</td><td>alpha</td><td>firefighter</td><td>").size())), 60);
}

}  // namespace
}  // namespace sarloc::test
