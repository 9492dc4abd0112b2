// The mission summary against the truth: what the picture knew and what each finder's device
// found, also when no incident command was left to put it in the picture.
#include <gtest/gtest.h>

#include "sarloc/core/mission/mission_summary.hpp"
#include "sarloc/core/mission/victim_matching.hpp"

namespace sarloc::mission {
namespace {

constexpr TimestampNs kEpoch = 1'763'800'000'000'000'000;
constexpr TimestampNs kSec = 1'000'000'000;

MissionScenario two_victims() {
  MissionScenario s;
  s.victims = {{"A", Vec3(0, 30, -1), Vec3(0.01, 0, 0), {}, {}}, {"B", Vec3(10, 30, -1), Vec3(0.01, 0, 0), {}, {}}};
  s.rescuers = {{"r1", "t", Vec3::Zero(), 90.0}, {"r2", "t", Vec3(10, 0, 0), 90.0}};
  return s;
}

DeviceSummary device(const std::string& id, std::vector<DeviceSignal> signals) {
  DeviceSummary d;
  d.rescuer_id = id;
  d.signals = std::move(signals);
  return d;
}

incident::FusedVictim victim(std::uint32_t id, const Vec3& p, incident::VictimState state, TimestampNs located) {
  incident::FusedVictim v;
  v.victim_id = id;
  v.position.position = p;
  v.state = state;
  v.located_at = located;
  return v;
}

TEST(MissionSummary, VictimsFoundOnlyByTheirFindersAreNamedWithTheFinders) {
  std::map<std::string, DeviceSummary> devices;
  devices["r1"] = device("r1", {{1, responder::EstimatorStatus::kFound, 0, 0.05, 0.3},
                                {2, responder::EstimatorStatus::kLocated, 1, std::nullopt, std::nullopt}});
  devices["r2"] = device("r2", {{1, responder::EstimatorStatus::kFound, 1, 0.07, 0.3},
                                {2, responder::EstimatorStatus::kFound, 0, 0.04, 0.3}});
  // The picture was lost while A was LOCATED and before B was seen.
  const std::vector<incident::FusedVictim> picture = {
      victim(1, Vec3(0.2, 30, -1), incident::VictimState::kLocated, kEpoch + 38 * kSec)};
  const auto s = summarise_mission("m", two_victims(), picture, kEpoch, devices);
  ASSERT_EQ(s.victims.size(), 2U);
  EXPECT_FALSE(s.all_found);
  EXPECT_EQ(s.found_count(), 0U);
  EXPECT_EQ(s.found_by_finder_count(), 2U);
  EXPECT_EQ(s.victims[0].finders, (std::vector<std::string>{"r1", "r2"}));
  EXPECT_EQ(s.victims[1].finders, (std::vector<std::string>{"r2"}));
  EXPECT_TRUE(s.victims[1].found_by_finder());
  EXPECT_FALSE(s.victims[1].victim_id.has_value()) << "B never reached the picture";
  ASSERT_EQ(s.fused_victims.size(), 1U);
  EXPECT_DOUBLE_EQ(*s.fused_victims[0].located_at_s, 38.0);
  EXPECT_FALSE(s.fused_victims[0].found_at_s.has_value());
}

TEST(MissionSummary, PictureOutcomesMatchTheTruth) {
  const std::vector<incident::FusedVictim> picture = {
      victim(4, Vec3(10.3, 30, -1), incident::VictimState::kFound, kEpoch + 40 * kSec),
      victim(9, Vec3(-40, 0, -1), incident::VictimState::kUnconfirmed, 0)};
  const auto p = picture_outcomes(two_victims(), picture, kEpoch);
  ASSERT_EQ(p.size(), 2U);
  EXPECT_EQ(p[0].victim_id, 4U);
  EXPECT_TRUE(p[0].matches_a_buried_victim);
  EXPECT_TRUE(p[0].found);
  EXPECT_DOUBLE_EQ(*p[0].located_at_s, 40.0);
  EXPECT_FALSE(p[1].matches_a_buried_victim);
  EXPECT_FALSE(p[1].located_at_s.has_value());
}

// Four within 5 m (a live failure): a second copy of A, 3 m from B, ended the mission as if B
// had been found, and B, never located, was missing from the final picture.
TEST(VictimMatching, ACopyOfOneVictimNeverStandsInForAnotherNearby) {
  MissionScenario s;
  s.victims = {{"A", Vec3(-1.5, 39.0, -1.2), Vec3(0.01, 0, 0), {}, {}}, {"B", Vec3(1.5, 40.0, -1.8), Vec3(0.01, 0, 0), {}, {}}};
  const std::vector<incident::FusedVictim> picture = {
      victim(2, Vec3(-1.3, 39.5, -1.1), incident::VictimState::kFound, kEpoch + 37 * kSec),
      victim(9, Vec3(-1.2, 39.0, -1.3), incident::VictimState::kFound, kEpoch + 45 * kSec)};
  EXPECT_FALSE(every_victim_found(s.victims, picture));
  const auto match = match_to_truth(s.victims, picture);
  EXPECT_GE(match[0], 0);
  EXPECT_EQ(match[1], -1) << "B matched by a copy of A";
  // B's own estimate, even if A's copies are nearer to each other than to anything else.
  auto with_b = picture;
  with_b.push_back(victim(3, Vec3(1.4, 40.2, -1.8), incident::VictimState::kFound, kEpoch + 50 * kSec));
  EXPECT_TRUE(every_victim_found(s.victims, with_b));
  EXPECT_EQ(match_to_truth(s.victims, with_b)[1], 2);
}

// A transmitter split by every device: incident command holds C twice, the FOUND copy 0.8 m
// from it and an unconfirmed twin 0.5 m from it that names the FOUND one. C is found; the FOUND
// copy is no ghost. Matched by distance alone, the twin took C (live, four within 5 m, clean
// seed 1: "C not found" and a "ghost" that was C's own FOUND).
TEST(VictimMatching, AConfirmedVictimIsMatchedBeforeItsUnconfirmedTwin) {
  MissionScenario s;
  s.victims = {{"C", Vec3(0.0, 42.0, -1.0), Vec3(0.01, 0, 0), {}, {}}};
  std::vector<incident::FusedVictim> picture = {
      victim(2, Vec3(-0.53, 41.95, -1.25), incident::VictimState::kUnconfirmed, 0),
      victim(10, Vec3(0.66, 42.45, -1.03), incident::VictimState::kFound, kEpoch + 60 * kSec)};
  picture[0].possibly_same_as = 10;
  EXPECT_EQ(match_to_truth(s.victims, picture)[0], 1);
  EXPECT_TRUE(every_victim_found(s.victims, picture));
  const auto p = picture_outcomes(s, picture, kEpoch);
  EXPECT_FALSE(p[0].matches_a_buried_victim);
  EXPECT_TRUE(p[1].matches_a_buried_victim);
}

// What sarloc-mission saw at its end, in the summary's terms: alarms and links as text, times
// in mission seconds.
TEST(MissionSummary, TheMissionsEndIsAssembledInTheSummarysTerms) {
  MissionEnd end;
  end.picture = {victim(1, Vec3(0.1, 30, -1), incident::VictimState::kFound, kEpoch + 20 * kSec)};
  incident::IncidentAlarm lost;
  lost.alarm_id = 4;
  lost.alarm.responder_id = "r2";
  lost.alarm.kind = responder::AlarmKind::kLinkLost;
  lost.alarm.raised_at = kEpoch + 41 * kSec;
  lost.alarm.active = false;
  lost.alarm.cleared_at = kEpoch + 47500 * (kSec / 1000);
  end.alarms = {lost};
  end.links = {{"r1", incident::LinkState::kSignedOff}, {"r2", incident::LinkState::kLost}};
  FaultOutcome kill;
  kill.action = "kill";
  kill.target = "r2";
  end.faults = {kill};
  end.firefighters_without_summary = {"ff1"};
  end.mission_s = 60.0;
  end.wall_s = 30.5;
  end.picture_available = false;
  const auto s = assemble_mission_summary("m", two_victims(), kEpoch, end);
  EXPECT_TRUE(s.victims[0].found);
  EXPECT_FALSE(s.all_found) << "B was not found";
  ASSERT_EQ(s.picture_alarms.size(), 1U);
  EXPECT_EQ(s.picture_alarms[0].alarm_id, 4U);
  EXPECT_EQ(s.picture_alarms[0].kind, "link_lost");
  EXPECT_DOUBLE_EQ(s.picture_alarms[0].raised_s, 41.0);
  ASSERT_TRUE(s.picture_alarms[0].cleared_s);
  EXPECT_DOUBLE_EQ(*s.picture_alarms[0].cleared_s, 47.5);
  EXPECT_EQ(s.links_at_end, (std::map<std::string, std::string>{{"r1", "signed_off"}, {"r2", "lost"}}));
  ASSERT_EQ(s.faults.size(), 1U);
  EXPECT_EQ(s.faults[0].target, "r2");
  EXPECT_EQ(s.firefighters_without_summary, std::vector<std::string>{"ff1"});
  EXPECT_DOUBLE_EQ(s.mission_s, 60.0);
  EXPECT_DOUBLE_EQ(s.wall_s, 30.5);
  EXPECT_TRUE(s.command_alive_at_end);
  EXPECT_FALSE(s.picture_available);
}

}  // namespace
}  // namespace sarloc::mission
