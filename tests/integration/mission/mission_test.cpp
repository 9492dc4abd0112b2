// Whole missions as separate processes over DDS (sarloc-mission starts sarloc-core,
// sarloc-rescuer x N and sarloc-command): avalanche, building and mixed missions, and the core
// daemon killed or restarted. Their recordings, replays and the dashboard:
// mission_outputs_test.cpp; network faults and incident command killed: mission_faults_test.cpp.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "mission_record.hpp"
#include "record_comparison.hpp"
#include <vector>

#include "support/dds_test_domains.hpp"
#include "support/required_program.hpp"
#include "mission_runs.hpp"

namespace sarloc::test {
namespace {

TEST(Mission, SmallMissionFindsEveryVictimExactlyOnce) {
  const auto run = run_mission("small.yaml", kDomainMissionSmall);
  expect_complete(run);
  for (const auto& r : run.summary["rescuers"]) EXPECT_GT(r["distance_walked_m"].get<double>(), 5.0) << r.dump();
  // Issue 60: a mission that ends in order loses nobody. Every device signs off when stopped
  // (sign_off.hpp): every link ends signed off and the picture never held a link-lost alarm.
  EXPECT_EQ(run.summary["links_at_end"], json({{"r1", "signed_off"}, {"r2", "signed_off"}})) << run_report(run);
  for (const auto& a : run.summary["alarms"]) EXPECT_NE(a["kind"], "link_lost") << a.dump();
}

TEST(Mission, FourVictimsWithinFiveMetresNeverGiveAGhostOrAVictimTwice) {
  // config/missions/four-within-5m.yaml: pulses on nearly one period overlap for long stretches;
  // every device separates them itself. What must always hold is the safety of the picture:
  // every confirmed victim is a buried one, none is confirmed twice, no finder's FOUND lies
  // outside its stated radius, and what is found is where it is said to be. Finding all four is
  // a measured rate, not a guarantee (docs/benchmarks.md, "The whole mission with the realistic
  // receiver": a transmitter whose pulses the devices never separate stays unconfirmed); at
  // least three must be found, or the separation has regressed. A device may still track a
  // second signal of a found transmitter when the mission ends: the picture shows it as an
  // unconfirmed contact, never as a victim.
  // Info level: incident command logs every victim's state change, for a failure seen only in CI.
  const auto run = run_mission(std::string(SARLOC_SOURCE_DIR) + "/config/missions/four-within-5m.yaml",
                               kDomainMissionFourWithin5m, "--log-level info");
  ASSERT_FALSE(run.summary.is_null()) << "no summary; see " << run.run_dir;
  ASSERT_EQ(run.summary["true_victim_count"], 4);
  int confirmed = 0;
  bool one_to_one = true;
  for (const auto& v : run.summary["fused_victims"]) {
    if (!v["confirmed"].get<bool>()) {
      EXPECT_FALSE(v["found"].get<bool>()) << v.dump();
      continue;
    }
    ++confirmed;
    // One-to-one with the buried victims: a second copy of one matches none.
    EXPECT_TRUE(v["matches_a_buried_victim"].get<bool>()) << "a ghost or a victim twice: " << v.dump();
    one_to_one = one_to_one && v["matches_a_buried_victim"].get<bool>();
  }
  EXPECT_LE(confirmed, 4) << "a victim twice: " << run.summary["fused_victims"].dump();
  // Incident command's log of every victim's state change, for a failure seen only in CI.
  if (!one_to_one || confirmed > 4) ADD_FAILURE() << run_report(run);
  int found_by_finder = 0;
  for (const auto& v : run.summary["victims"]) {
    EXPECT_EQ(v.value("false_found", 0), 0) << v.dump();
    if (v["found_by_finder"].get<bool>()) {
      ++found_by_finder;
      ASSERT_FALSE(v["relative_error_m"].is_null()) << v.dump();
      EXPECT_LE(v["relative_error_m"].get<double>(), 0.5) << v.dump();
    }
    if (!v["found"].get<bool>()) continue;
    ASSERT_FALSE(v["error_m"].is_null()) << v.dump();
    EXPECT_LE(v["error_m"].get<double>(), 1.0) << v.dump();
  }
  // The separation's regression check: at least three victims found on the devices and
  // confirmed in the picture. Not "FOUND in the picture": a device's FOUND can stay out of the
  // picture, which then shows the victim LOCATED (docs/estimation/avalanche.md, "Left"; seen in
  // the fresh-clone CI of 2026-11-27 under load: C FOUND by r1 and confirmed from two other
  // devices' sources, LOCATED in the picture).
  EXPECT_GE(found_by_finder, 3) << run_report(run);
  EXPECT_GE(confirmed, 3) << run_report(run);
}

// Issue 63, item 5: A's finder reports it dug out; incident command keeps it, recovered, where it
// was found; every device switches A's transmitter off; B is still found, and nothing opens
// where A was.
TEST(Mission, AVictimDugOutStaysInThePictureAndItsTransmitterFallsSilent) {
  const auto run = run_mission("dug-out.yaml", kDomainMissionDugOut, "--log-level info");
  expect_complete(run);
  ASSERT_FALSE(run.summary.is_null()) << run_report(run);
  // B may be dug out too: its finder digs 5 mission s after its FOUND, and the rescuers can
  // still be running then while the mission stops (seen in CI on 2026-12-04).
  int a_dug_out = 0;
  for (const auto& v : run.summary["fused_victims"]) {
    if (!v["dug_out"].get<bool>()) continue;
    EXPECT_TRUE(v["found"].get<bool>()) << v.dump();
    EXPECT_TRUE(v["matches_a_buried_victim"].get<bool>()) << v.dump();
    if (v["position"][1].get<double>() < 20.0) ++a_dug_out;
  }
  EXPECT_EQ(a_dug_out, 1) << "A, found first, dug out once: " << run_report(run);
  EXPECT_EQ(run.summary["confirmed_fused_victim_count"], 2) << "nothing new where A was: " << run_report(run);
  EXPECT_NE(file_text(run.run_dir / "command-1.log").find("dug out (reported by 'r"), std::string::npos)
      << run_report(run);
  for (const char* device : {"rescuer-r1.log", "rescuer-r2.log"}) {
    EXPECT_NE(file_text(run.run_dir / device).find("the transmitter of 'A' is switched off"), std::string::npos)
        << device;
  }
}

TEST(Mission, KilledRescuerIsReportedLinkLostWithinTheLease) {
  const auto run = run_mission("small.yaml", kDomainMissionSmall + 1, "--kill r2@12");
  ASSERT_FALSE(run.summary.is_null()) << file_text(run.run_dir / "mission.out");
  ASSERT_EQ(run.summary["faults"].size(), 1U);
  const auto& fault = run.summary["faults"][0];
  ASSERT_TRUE(fault.contains("link_lost_after_s")) << "incident command never reported r2's link lost";
  // Lease 3 s (config/dds/topics.xml, responder_position) + one command cycle (0.25 s) +
  // delivery: anything later means the lease is not what detects a dead device.
  EXPECT_LE(fault["link_lost_after_s"].get<double>(), 3.0 + 0.25 + 0.75);
  // r1 alone still finds both victims.
  expect_complete(run);
  // At the end r1, stopped in order, signed off; the killed r2 stays lost.
  EXPECT_EQ(run.summary["links_at_end"], json({{"r1", "signed_off"}, {"r2", "lost"}})) << run_report(run);
}

// Issue 14's building test: every firefighter converges to <= 1.5 m RMSE, the motionless alarm
// fires within its timeout plus one second of the stop (and clears), and a killed firefighter's
// device is reported link lost within the lease.
TEST(Mission, BuildingFirefightersConvergeRaiseTheMotionlessAlarmAndAKilledOneIsLinkLost) {
  const auto run = run_mission("building-small.yaml", kDomainMissionBuilding, "--kill ff3@70");
  ASSERT_FALSE(run.summary.is_null()) << file_text(run.run_dir / "mission.out");
  const auto& firefighters = run.summary["firefighters"];
  ASSERT_EQ(firefighters.size(), 2U) << "ff1 and ff2 report; ff3 was killed: " << run_report(run);
  bool motionless_seen = false;
  for (const auto& f : firefighters) {
    ASSERT_TRUE(f.contains("rmse_after_convergence_m")) << f.dump();
    EXPECT_LE(f["rmse_after_convergence_m"].get<double>(), 1.5) << f.dump();
    EXPECT_EQ(f["confirmed_outside_99"].get<int>(), 0) << f.dump();
    for (const auto& a : f["alarms"]) {
      if (a["kind"] != "motionless") continue;
      ASSERT_EQ(f["responder_id"], "ff2") << "only ff2 stopped: " << f.dump();
      ASSERT_TRUE(a.contains("delay_s")) << "the scripted stop's alarm: " << a.dump();
      EXPECT_GE(a["delay_s"].get<double>(), -0.5) << a.dump();
      EXPECT_LE(a["delay_s"].get<double>(), 1.0) << "within its timeout plus one second: " << a.dump();
      ASSERT_TRUE(a.contains("cleared_s")) << "walking on clears it: " << a.dump();
      EXPECT_LE(a["clear_delay_s"].get<double>(), 1.0) << a.dump();
      motionless_seen = true;
    }
  }
  EXPECT_TRUE(motionless_seen) << run_report(run);
  EXPECT_EQ(run.summary["firefighters_without_summary"], json::array({"ff3"}));
  ASSERT_EQ(run.summary["faults"].size(), 1U);
  const auto& fault = run.summary["faults"][0];
  ASSERT_TRUE(fault.contains("link_lost_after_s")) << "incident command never reported ff3's link lost: " << run_report(run);
  // Within the 3 s lease (+ a command cycle + delivery), wall time. building-small.yaml makes the
  // silence rule wait 60 mission s (7.5 wall s), so this is the device writer's MANUAL_BY_TOPIC
  // liveliness (config/dds/topics.xml, responder_position.device).
  EXPECT_LE(fault["link_lost_after_s"].get<double>(), 3.0 + 0.25 + 0.75);
  // The picture held the alarms: ff2's motionless one and ff3's link lost.
  // ff1's mayday (raised at 50 s, reset at 65 s) too.
  bool motionless_in_picture = false, link_lost_in_picture = false, mayday_in_picture = false;
  for (const auto& a : run.summary["alarms"]) {
    motionless_in_picture = motionless_in_picture || (a["kind"] == "motionless" && a["responder_id"] == "ff2");
    link_lost_in_picture = link_lost_in_picture || (a["kind"] == "link_lost" && a["responder_id"] == "ff3");
    if (a["kind"] == "mayday" && a["responder_id"] == "ff1") {
      mayday_in_picture = true;
      EXPECT_NEAR(a["raised_s"].get<double>(), 50.0, 0.6) << a.dump();
      ASSERT_TRUE(a.contains("cleared_s")) << "reset: " << a.dump();
      EXPECT_NEAR(a["cleared_s"].get<double>(), 65.0, 0.6) << a.dump();
    }
  }
  EXPECT_TRUE(motionless_in_picture) << run.summary["alarms"].dump();
  EXPECT_TRUE(link_lost_in_picture) << run.summary["alarms"].dump();
  EXPECT_TRUE(mayday_in_picture) << run.summary["alarms"].dump();
  EXPECT_EQ(run.summary["links_at_end"], json({{"ff1", "signed_off"}, {"ff2", "signed_off"}, {"ff3", "lost"}}))
      << run_report(run);
}

// The core daemon killed mid-search and restarted: the firefighters' devices dead reckon from
// their last fix meanwhile, and the new daemon, meeting them mid-search, starts them from an
// unknown state, never at the door: nothing it confirms is wrong.
TEST(Mission, BuildingDevicesDeadReckonWhileTheDaemonIsDownAndTheNewOneConfirmsNothingWrong) {
  const auto run = run_mission("building-small.yaml", kDomainMissionBuildingDaemonKill, "--kill core@50 --restart core@65");
  ASSERT_FALSE(run.summary.is_null()) << file_text(run.run_dir / "mission.out");
  ASSERT_EQ(run.summary["firefighters"].size(), 3U) << run_report(run);
  for (const auto& f : run.summary["firefighters"]) {
    EXPECT_GE(f["dead_reckoning_s"].get<double>(), 10.0) << "on its own while the daemon was down: " << f.dump();
    EXPECT_EQ(f["confirmed_outside_99"].get<int>(), 0) << f.dump();
    // Before the kill at 50 s the daemon answered at most 80 steps (2 Hz from 10 s): the rest came
    // from the restarted one.
    EXPECT_GT(f["fixes"].get<int>(), 100) << "the restarted daemon answers too: " << f.dump();
    // The restarted daemon starts near each device's own reckoning (firefighter.hint_*), and the
    // device keeps its reckoning through the new daemon's first, unsure answers: before both, the
    // restarted daemon's fixes were 3.0-3.7 m off (RMSE) and the devices' own positions up to
    // 4.9-7.5 m (docs/estimation/firefighter.md, "A daemon that meets the firefighter mid-search").
    ASSERT_TRUE(f.contains("rmse_after_convergence_m")) << f.dump();
    EXPECT_LT(f["rmse_after_convergence_m"].get<double>(), 1.2) << f.dump();
    ASSERT_TRUE(f.contains("own_max_error_m")) << f.dump();
    EXPECT_LT(f["own_max_error_m"].get<double>(), 2.0) << "the device's own position: " << f.dump();
    EXPECT_LE(f["own_outside_99"].get<int>(), f["own_positions"].get<int>() / 50 + 1) << f.dump();
  }
}

// A mission may hold both kinds of responders: one core daemon serves the avalanche rescuers
// and the firefighters at once, and the victims are found while the firefighters are located.
TEST(Mission, OneDaemonServesAvalancheRescuersAndFirefightersAtOnce) {
  const auto run = run_mission("mixed.yaml", kDomainMissionMixed);
  expect_complete(run);
  ASSERT_EQ(run.summary["firefighters"].size(), 2U) << run_report(run);
  for (const auto& f : run.summary["firefighters"]) {
    ASSERT_TRUE(f.contains("rmse_after_convergence_m")) << f.dump();
    EXPECT_LE(f["rmse_after_convergence_m"].get<double>(), 1.5) << f.dump();
    EXPECT_GT(f["fixes"].get<int>(), 100) << "the daemon answered the firefighter all along: " << f.dump();
  }
}

TEST(Mission, KilledDaemonLeavesRescuersGuidingOnTheirDevices) {
  const auto run = run_mission("small.yaml", kDomainMissionSmall + 2, "--kill core@10");
  expect_complete(run);
  int fallbacks = 0;
  for (const auto& r : run.summary["rescuers"]) fallbacks += r.value("fallbacks", 0);
  EXPECT_GE(fallbacks, 1) << "no rescuer noticed the daemon was gone";
}

// A restarted daemon starts with empty filters: the devices keep their own guidance until the
// daemon's estimates catch up with theirs, then follow the daemon again; nothing is lost.
TEST(Mission, RestartedDaemonTakesOverAgainWithoutLosingTheSearch) {
  const auto run = run_mission("small.yaml", kDomainMissionSmall + 3, "--kill core@8 --restart core@16");
  expect_complete(run);
  int fallbacks = 0;
  int resumed = 0;
  for (const auto& r : run.summary["rescuers"]) {
    fallbacks += r.value("fallbacks", 0);
    resumed += r.value("daemon_after_fallback", 0);
  }
  EXPECT_GE(fallbacks, 1) << "no rescuer noticed the daemon was gone";
  EXPECT_GT(resumed, 0) << "no rescuer followed the restarted daemon again";
}

}  // namespace
}  // namespace sarloc::test
