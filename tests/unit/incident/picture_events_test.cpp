// What changed in the incident picture, in words, dated by the samples: the one derivation the
// dashboard's event log and the report's timeline share.
#include "sarloc/core/incident/picture_events.hpp"

#include <gtest/gtest.h>

namespace sarloc::incident {
namespace {

constexpr TimestampNs kS = 1'000'000'000LL;

FusedVictim victim(std::uint32_t id, VictimState state) {
  FusedVictim v;
  v.victim_id = id;
  v.position.position = Vec3(12.34, -5.0, -1.0);
  v.position.covariance = Mat3::Identity() * 0.01;
  v.state = state;
  v.first_seen = 10 * kS;
  v.last_update = 50 * kS;
  if (state != VictimState::kUnconfirmed) v.located_at = 30 * kS;
  if (is_found(state)) v.found_at = 40 * kS;
  return v;
}

std::vector<std::string> texts(const std::vector<PictureEvent>& events) {
  std::vector<std::string> out;
  for (const auto& e : events) out.push_back(e.text);
  return out;
}

// A victim seen for the first time already FOUND (a dashboard started late, a recording cut
// in): each step it carries a time for, in order, at that time.
TEST(PictureEvents, AVictimFirstSeenFoundGivesEachStepAtItsOwnTime) {
  PictureEvents events;
  const auto out = events.on_victim(victim(3, VictimState::kFound));
  ASSERT_EQ(out.size(), 3u) << ::testing::PrintToString(texts(out));
  EXPECT_EQ(out[0].text, "victim 3 in the picture at (12.3, -5.0)");
  EXPECT_EQ(out[0].stamp, 10 * kS);
  EXPECT_EQ(out[1].text, "victim 3 LOCATED at (12.3, -5.0)");
  EXPECT_EQ(out[1].stamp, 30 * kS);
  EXPECT_EQ(out[2].text, "victim 3 FOUND at (12.3, -5.0), 95 % radius 0.2 m");
  EXPECT_EQ(out[2].stamp, 40 * kS);
  for (const auto& e : out) EXPECT_EQ(e.kind, "victim");
  // The same sample again, or a newer one of the same state: nothing new.
  EXPECT_TRUE(events.on_victim(victim(3, VictimState::kFound)).empty());
}

// Step by step: each transition once; a withdrawn confirmation says so and makes the next
// LOCATED news again; recovery and the evidence flag both ways.
TEST(PictureEvents, TransitionsOfOneVictimAreEachReportedOnce) {
  PictureEvents events;
  EXPECT_EQ(texts(events.on_victim(victim(1, VictimState::kUnconfirmed))),
            std::vector<std::string>{"victim 1 in the picture at (12.3, -5.0)"});
  EXPECT_EQ(texts(events.on_victim(victim(1, VictimState::kLocated))),
            std::vector<std::string>{"victim 1 LOCATED at (12.3, -5.0)"});
  EXPECT_EQ(texts(events.on_victim(victim(1, VictimState::kUnconfirmed))),
            std::vector<std::string>{"victim 1 back to unconfirmed: its confirmation was withdrawn"});
  EXPECT_EQ(texts(events.on_victim(victim(1, VictimState::kLocated))),
            std::vector<std::string>{"victim 1 LOCATED at (12.3, -5.0)"});
  auto conflicted = victim(1, VictimState::kLocated);
  conflicted.evidence_conflict = true;
  const auto disagree = events.on_victim(conflicted);
  ASSERT_EQ(disagree.size(), 1u);
  EXPECT_NE(disagree[0].text.find("DISAGREE"), std::string::npos);
  EXPECT_EQ(disagree[0].stamp, 50 * kS);
  EXPECT_TRUE(events.on_victim(conflicted).empty());
  EXPECT_EQ(texts(events.on_victim(victim(1, VictimState::kLocated))),
            std::vector<std::string>{"victim 1: its sources agree again"});
  EXPECT_EQ(texts(events.on_victim(victim(1, VictimState::kFound))).size(), 1u);
  EXPECT_EQ(texts(events.on_victim(victim(1, VictimState::kLocated))),
            std::vector<std::string>{"victim 1 back to LOCATED: its confirmation was withdrawn"});
  EXPECT_EQ(texts(events.on_victim(victim(1, VictimState::kFound))),
            std::vector<std::string>{"victim 1 FOUND at (12.3, -5.0), 95 % radius 0.2 m"});
  EXPECT_EQ(texts(events.on_victim(victim(1, VictimState::kRecovered))),
            std::vector<std::string>{"victim 1 recovered (dug out)"});
  EXPECT_EQ(texts(events.on_victim_gone(1, 60 * kS)),
            std::vector<std::string>{"victim 1 merged into another (same transmitter)"});
  EXPECT_TRUE(events.on_victim_gone(1, 61 * kS).empty()) << "gone twice";
  EXPECT_TRUE(events.on_victim_gone(7, 61 * kS).empty()) << "never seen";
}

TeamStatus team(LinkState link, AccountabilityState accountability, TimestampNs stamp) {
  MemberStatus m;
  m.responder_id = "ff1";
  m.link = link;
  m.accountability = accountability;
  return {"alpha", {m}, stamp};
}

// A member's first status is no change; then link and accountability, each when it changes.
TEST(PictureEvents, LinkAndAccountabilityChangesOfAMember) {
  PictureEvents events;
  EXPECT_TRUE(events.on_team(team(LinkState::kAlive, AccountabilityState::kAccounted, 1 * kS)).empty());
  EXPECT_TRUE(events.on_team(team(LinkState::kAlive, AccountabilityState::kAccounted, 2 * kS)).empty());
  const auto lost = events.on_team(team(LinkState::kLost, AccountabilityState::kMissing, 12 * kS));
  ASSERT_EQ(lost.size(), 2u);
  EXPECT_EQ(lost[0].kind, "link");
  EXPECT_EQ(lost[0].text, "ff1 (alpha): link LOST");
  EXPECT_EQ(lost[0].stamp, 12 * kS);
  EXPECT_EQ(lost[1].kind, "accountability");
  EXPECT_EQ(lost[1].text, "ff1 (alpha): MISSING at the check");
  EXPECT_EQ(texts(events.on_team(team(LinkState::kAlive, AccountabilityState::kAccounted, 18 * kS))),
            (std::vector<std::string>{"ff1 (alpha): link alive again (regained)", "ff1 (alpha): accounted for"}));
  EXPECT_EQ(texts(events.on_team(team(LinkState::kSignedOff, AccountabilityState::kAccounted, 30 * kS))),
            std::vector<std::string>{"ff1 (alpha): signed off (the device stopped in order)"});
}

IncidentAlarm alarm(bool acknowledged, bool active) {
  IncidentAlarm a;
  a.alarm_id = 5;
  a.alarm.kind = responder::AlarmKind::kMayday;
  a.alarm.responder_id = "ff1";
  a.alarm.raised_at = 21 * kS;
  a.alarm.active = active;
  if (!active) a.alarm.cleared_at = 25 * kS;
  a.acknowledged = acknowledged;
  if (acknowledged) {
    a.acknowledged_by = "ic";
    a.acknowledged_at = 23 * kS;
  }
  return a;
}

TEST(PictureEvents, AnAlarmRaisedAcknowledgedClearedAndClosed) {
  PictureEvents events;
  const auto raised = events.on_alarm(alarm(false, true));
  ASSERT_EQ(raised.size(), 1u);
  EXPECT_EQ(raised[0].text, "MAYDAY alarm 5 for ff1 RAISED");
  EXPECT_EQ(raised[0].stamp, 21 * kS);
  const auto acknowledged = events.on_alarm(alarm(true, true));
  ASSERT_EQ(acknowledged.size(), 1u);
  EXPECT_EQ(acknowledged[0].text, "MAYDAY alarm 5 for ff1 acknowledged by ic");
  EXPECT_EQ(acknowledged[0].stamp, 23 * kS);
  const auto cleared = events.on_alarm(alarm(true, false));
  ASSERT_EQ(cleared.size(), 1u);
  EXPECT_EQ(cleared[0].text, "MAYDAY alarm 5 for ff1 cleared");
  EXPECT_EQ(cleared[0].stamp, 25 * kS);
  EXPECT_TRUE(events.on_alarm(alarm(true, false)).empty());
  EXPECT_EQ(texts(events.on_alarm_gone(5, 26 * kS)), std::vector<std::string>{"alarm 5 closed"});

  // First seen already acknowledged and cleared: all three, each at its time.
  PictureEvents late;
  const auto all = late.on_alarm(alarm(true, false));
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].stamp, 21 * kS);
  EXPECT_EQ(all[1].stamp, 23 * kS);
  EXPECT_EQ(all[2].stamp, 25 * kS);
}

// A new episode of an alarm nobody acknowledged reopens it (AlarmBoard): told as raised again, and
// its clear too when both come in one sample.
TEST(PictureEvents, AnAlarmReopenedByANewEpisodeIsRaisedAgain) {
  PictureEvents events;
  events.on_alarm(alarm(false, false));
  auto again = alarm(false, true);
  again.alarm.raised_at = 40 * kS;
  const auto raised = events.on_alarm(again);
  ASSERT_EQ(raised.size(), 1u);
  EXPECT_EQ(raised[0].text, "MAYDAY alarm 5 for ff1 RAISED again");
  EXPECT_EQ(raised[0].stamp, 40 * kS);
  EXPECT_TRUE(events.on_alarm(again).empty());
  auto over = alarm(false, false);
  over.alarm.raised_at = 50 * kS;
  over.alarm.cleared_at = 55 * kS;
  EXPECT_EQ(texts(events.on_alarm(over)),
            (std::vector<std::string>{"MAYDAY alarm 5 for ff1 RAISED again", "MAYDAY alarm 5 for ff1 cleared"}));
}

responder::ResponderPosition fix(responder::PositionSource source, bool suspected, TimestampNs stamp) {
  responder::ResponderPosition p;
  p.responder_id = "ff2";
  p.source = source;
  p.map_error_suspected = suspected;
  p.stamp = stamp;
  p.position.position = Vec3(4.0, 7.3, 0.0);
  return p;
}

// Map-aided fixes only, in time order: an older or repeated fix (the daemon's copy of a silent
// firefighter's last one) and dead reckoning change nothing.
TEST(PictureEvents, TheFloorPlanSuspicionOnAndOffFromMapAidedFixesOnly) {
  using responder::PositionSource;
  PictureEvents events;
  EXPECT_TRUE(events.on_position(fix(PositionSource::kMapAided, false, 1 * kS)).empty());
  EXPECT_TRUE(events.on_position(fix(PositionSource::kDeadReckoning, true, 2 * kS)).empty());
  const auto on = events.on_position(fix(PositionSource::kMapAided, true, 25 * kS));
  ASSERT_EQ(on.size(), 1u);
  EXPECT_EQ(on[0].kind, "map error");
  EXPECT_EQ(on[0].text, "ff2: the map-aided filter suspects the floor plan near (4.0, 7.3)");
  EXPECT_EQ(on[0].stamp, 25 * kS);
  EXPECT_TRUE(events.on_position(fix(PositionSource::kMapAided, false, 24 * kS)).empty()) << "older";
  EXPECT_TRUE(events.on_position(fix(PositionSource::kMapAided, false, 25 * kS)).empty()) << "same stamp";
  EXPECT_EQ(texts(events.on_position(fix(PositionSource::kMapAided, false, 27 * kS))),
            std::vector<std::string>{"ff2: map error no longer suspected"});
}

}  // namespace
}  // namespace sarloc::incident
