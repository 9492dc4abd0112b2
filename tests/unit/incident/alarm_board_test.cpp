// Incident command's alarm board: an alarm stays until it is acknowledged and cleared, a device's
// raise and clear are one alarm in any order, one alarm per (responder, kind) that a new episode
// reopens until someone acknowledges it, and a standby adopts the active board with its ids.
#include <gtest/gtest.h>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/alarm_board.hpp"

namespace sarloc::incident {
namespace {

using responder::AlarmKind;

responder::ResponderAlarm device_alarm(AlarmKind kind, TimestampNs raised, bool active, TimestampNs cleared = 0) {
  responder::ResponderAlarm a;
  a.responder_id = "ff1";
  a.team_id = "alpha";
  a.kind = kind;
  a.raised_at = raised;
  a.active = active;
  a.cleared_at = cleared;
  return a;
}

TEST(AlarmBoard, AnAlarmStaysUntilAcknowledgedAndCleared) {
  AlarmBoard board;
  board.on_device_alarm(device_alarm(AlarmKind::kMotionless, 100, true), 101);
  ASSERT_EQ(board.alarms().size(), 1U);
  const auto id = board.alarms()[0].alarm_id;
  EXPECT_EQ(board.acknowledge(id, "ic", 102, 102), AckResult::kAcknowledged);
  EXPECT_EQ(board.acknowledge(id, "ic", 103, 103), AckResult::kAlready);
  ASSERT_EQ(board.alarms().size(), 1U) << "acknowledged but still active: stays";
  EXPECT_TRUE(board.alarms()[0].acknowledged);
  EXPECT_TRUE(board.take_removed().empty());
  board.on_device_alarm(device_alarm(AlarmKind::kMotionless, 100, false, 150), 151);
  EXPECT_TRUE(board.alarms().empty()) << "acknowledged and cleared: gone";
  EXPECT_EQ(board.take_removed(), std::vector<std::uint32_t>{id});
  EXPECT_EQ(board.acknowledge(id, "ic", 160, 160), AckResult::kUnknown);
}

TEST(AlarmBoard, AClearedAlarmNobodyAcknowledgedIsStillShown) {
  AlarmBoard board;
  board.on_device_alarm(device_alarm(AlarmKind::kMotionless, 100, true), 101);
  board.on_device_alarm(device_alarm(AlarmKind::kMotionless, 100, false, 130), 131);
  ASSERT_EQ(board.alarms().size(), 1U);
  EXPECT_FALSE(board.alarms()[0].alarm.active);
  EXPECT_EQ(board.alarms()[0].alarm.cleared_at, 130);
  // A clear whose raise never arrived (the raise was lost, or command started late) shows too.
  board.on_device_alarm(device_alarm(AlarmKind::kMayday, 200, false, 220), 221);
  EXPECT_EQ(board.alarms().size(), 2U);
  // The raise arriving after its clear changes nothing.
  board.on_device_alarm(device_alarm(AlarmKind::kMayday, 200, true), 222);
  EXPECT_EQ(board.alarms().size(), 2U);
  EXPECT_EQ(board.active_count(), 0U);
  // A new raise of the same kind nobody acknowledged the last of: the same alarm, active again.
  const auto motionless = board.alarms()[0].alarm_id;
  board.on_device_alarm(device_alarm(AlarmKind::kMotionless, 300, true), 301);
  ASSERT_EQ(board.alarms().size(), 2U);
  EXPECT_EQ(board.alarms()[0].alarm_id, motionless);
  EXPECT_EQ(board.alarms()[0].alarm.raised_at, 300);
  EXPECT_TRUE(board.alarms()[0].alarm.active);
  EXPECT_EQ(board.active_count(), 1U);
  // The earlier episode's samples, arriving late, change nothing.
  board.on_device_alarm(device_alarm(AlarmKind::kMotionless, 100, false, 130), 302);
  board.on_device_alarm(device_alarm(AlarmKind::kMotionless, 100, true), 303);
  EXPECT_EQ(board.alarms().size(), 2U);
  EXPECT_EQ(board.alarms()[0].alarm.raised_at, 300);
  EXPECT_TRUE(board.alarms()[0].alarm.active);
}

TEST(AlarmBoard, AnAcknowledgedAlarmIsAnsweredAndTheNextEpisodeIsANewAlarm) {
  AlarmBoard board;
  board.on_device_alarm(device_alarm(AlarmKind::kMayday, 100, true), 101);
  const auto first = board.alarms()[0].alarm_id;
  EXPECT_EQ(board.acknowledge(first, "ic", 102, 102), AckResult::kAcknowledged);
  // The device's clear was lost; its next raise is a new mayday to answer, and the first goes.
  board.on_device_alarm(device_alarm(AlarmKind::kMayday, 200, true), 201);
  ASSERT_EQ(board.alarms().size(), 1U);
  EXPECT_NE(board.alarms()[0].alarm_id, first);
  EXPECT_FALSE(board.alarms()[0].acknowledged);
  EXPECT_EQ(board.alarms()[0].alarm.raised_at, 200);
  EXPECT_EQ(board.take_removed(), std::vector<std::uint32_t>{first});
  // A condition acknowledged while active, cleared, and raised again: a new alarm.
  board.set_condition("ff2", "alpha", AlarmKind::kLinkLost, true, 300);
  const auto link = board.alarms().back().alarm_id;
  EXPECT_EQ(board.acknowledge(link, "ic", 301, 301), AckResult::kAcknowledged);
  board.set_condition("ff2", "alpha", AlarmKind::kLinkLost, false, 310);
  EXPECT_EQ(board.take_removed(), std::vector<std::uint32_t>{link});
  board.set_condition("ff2", "alpha", AlarmKind::kLinkLost, true, 320);
  EXPECT_GT(board.alarms().back().alarm_id, link);
  EXPECT_FALSE(board.alarms().back().acknowledged);
}

TEST(AlarmBoard, AConditionThatComesAndGoesIsOneAlarmUntilAcknowledged) {
  AlarmBoard board;
  for (TimestampNs t = 0; t < 5; ++t) board.set_condition("ff1", "alpha", AlarmKind::kLinkLost, true, 10 + t);
  ASSERT_EQ(board.alarms().size(), 1U);
  EXPECT_EQ(board.alarms()[0].alarm.raised_at, 10);
  const auto id = board.alarms()[0].alarm_id;
  board.set_condition("ff1", "alpha", AlarmKind::kLinkLost, false, 20);
  board.set_condition("ff1", "alpha", AlarmKind::kLinkLost, false, 21);
  EXPECT_EQ(board.alarms()[0].alarm.cleared_at, 20);
  EXPECT_EQ(board.active_count(), 0U);
  board.set_condition("ff1", "alpha", AlarmKind::kLinkLost, true, 30, GaussianPosition{}, 2);
  ASSERT_EQ(board.alarms().size(), 1U) << "cleared and unacknowledged: the second episode reopens it";
  EXPECT_EQ(board.alarms()[0].alarm_id, id);
  EXPECT_TRUE(board.alarms()[0].alarm.active);
  EXPECT_EQ(board.alarms()[0].alarm.raised_at, 30);
  EXPECT_EQ(board.alarms()[0].alarm.cleared_at, 0);
  EXPECT_TRUE(board.alarms()[0].alarm.position_known);
  EXPECT_EQ(board.alarms()[0].alarm.floor, 2);
  // A map error flickering at a doorway for hours, for 200 firefighters: 200 alarms, not one
  // per episode (670 in an hour before, each republished every cycle).
  for (int episode = 0; episode < 50; ++episode) {
    for (int f = 0; f < 200; ++f) {
      const std::string who = "ff" + std::to_string(f);
      board.set_condition(who, "crew", AlarmKind::kMapError, true, 100 + 2 * episode);
      board.set_condition(who, "crew", AlarmKind::kMapError, false, 101 + 2 * episode);
    }
  }
  EXPECT_EQ(board.alarms().size(), 201U);
  EXPECT_TRUE(board.take_removed().empty());
  EXPECT_EQ(board.acknowledge(id, "ic", 40, 40), AckResult::kAcknowledged);
  EXPECT_EQ(board.alarms()[0].alarm_id, id) << "acknowledged while active: stays";
}

TEST(AlarmBoard, StandbyAdoptsTheActiveBoardAndGoesOnWithItsIds) {
  AlarmBoard active;
  active.on_device_alarm(device_alarm(AlarmKind::kMayday, 100, true), 101);
  active.set_condition("ff2", "alpha", AlarmKind::kLinkLost, true, 110);
  AlarmBoard standby;
  standby.adopt(active.alarms());
  EXPECT_EQ(standby.alarms().size(), 2U);
  // The device's clear and the link's return reach the standby after it took over.
  standby.on_device_alarm(device_alarm(AlarmKind::kMayday, 100, false, 140), 141);
  standby.set_condition("ff2", "alpha", AlarmKind::kLinkLost, false, 142);
  EXPECT_EQ(standby.alarms().size(), 2U);
  EXPECT_EQ(standby.active_count(), 0U);
  // New alarms continue after the adopted ids.
  standby.set_condition("ff3", "bravo", AlarmKind::kMapError, true, 150);
  EXPECT_GT(standby.alarms().back().alarm_id, active.alarms().back().alarm_id);
  // The adopted alarms are still each one's condition: a new episode reopens them.
  standby.set_condition("ff2", "alpha", AlarmKind::kLinkLost, true, 160);
  EXPECT_EQ(standby.alarms().size(), 3U);
  EXPECT_EQ(standby.active_count(), 2U);
}

TEST(AlarmBoard, AdoptingSeveralAlarmsOfOneConditionGoesOnWithTheNewestEpisode) {
  // A board published before one alarm per (responder, kind): four episodes of ff1's mayday, the
  // highest id a clear whose raise never came, of an episode older than the active one.
  const auto adopted = [](std::uint32_t id, TimestampNs raised, bool active, bool acknowledged) {
    IncidentAlarm a;
    a.alarm_id = id;
    a.alarm = device_alarm(AlarmKind::kMayday, raised, active, active ? 0 : raised + 5);
    a.acknowledged = acknowledged;
    return a;
  };
  AlarmBoard standby;
  standby.adopt({adopted(3, 100, true, false), adopted(4, 50, true, true), adopted(7, 200, true, false),
                 adopted(9, 150, false, false)});
  EXPECT_EQ(standby.take_removed(), std::vector<std::uint32_t>{4}) << "acknowledged, and its episode over";
  ASSERT_EQ(standby.alarms().size(), 3U);
  EXPECT_EQ(standby.active_count(), 1U) << "the newest episode, 7, is still a mayday";
  EXPECT_FALSE(standby.alarms()[0].alarm.active);
  EXPECT_EQ(standby.alarms()[0].alarm.cleared_at, 200) << "ended when the newer began";
  EXPECT_TRUE(standby.alarms()[1].alarm.active);
  EXPECT_EQ(standby.alarms()[1].alarm_id, 7U);
  standby.on_device_alarm(device_alarm(AlarmKind::kMayday, 200, false, 250), 251);
  EXPECT_EQ(standby.active_count(), 0U);
  // The older ones can still be answered and closed.
  EXPECT_EQ(standby.acknowledge(3, "ic", 260, 260), AckResult::kAcknowledged);
  EXPECT_EQ(standby.acknowledge(9, "ic", 260, 260), AckResult::kAcknowledged);
  EXPECT_EQ(standby.take_removed(), (std::vector<std::uint32_t>{3, 9}));
}

TEST(AlarmBoard, AnAcknowledgementMadeBeforeTheAlarmWentOffAgainLeavesItToBeAnswered) {
  AlarmBoard board;
  board.set_condition("ff1", "alpha", AlarmKind::kMapError, true, 100);
  board.set_condition("ff1", "alpha", AlarmKind::kMapError, false, 110);
  const auto id = board.alarms()[0].alarm_id;
  board.set_condition("ff1", "alpha", AlarmKind::kMapError, true, 130);
  // The operator answered the cleared row at 125; it arrives after the alarm went off again.
  EXPECT_EQ(board.acknowledge(id, "ic", 125, 131), AckResult::kEarlierEpisode);
  ASSERT_EQ(board.alarms().size(), 1U);
  EXPECT_FALSE(board.alarms()[0].acknowledged);
  EXPECT_TRUE(board.alarms()[0].alarm.active);
  EXPECT_EQ(board.acknowledge(id, "ic", 140, 141), AckResult::kAcknowledged);

  // A device whose clock is a minute ahead: its first mayday, acknowledged at once, is answered.
  board.on_device_alarm(device_alarm(AlarmKind::kMayday, 60'000, true), 200);
  const auto mayday = board.alarms().back().alarm_id;
  EXPECT_EQ(board.acknowledge(mayday, "ic", 210, 211), AckResult::kAcknowledged);
}

TEST(AlarmBoard, ADeviceRaiseIsNeverHiddenEvenWithAnEarlierStamp) {
  AlarmBoard board;
  board.on_device_alarm(device_alarm(AlarmKind::kMayday, 500, true), 501);
  board.on_device_alarm(device_alarm(AlarmKind::kMayday, 500, false, 520), 521);
  // The device restarted with its clock behind: its next mayday is stamped earlier.
  board.on_device_alarm(device_alarm(AlarmKind::kMayday, 40, true), 530);
  ASSERT_EQ(board.alarms().size(), 1U);
  EXPECT_TRUE(board.alarms()[0].alarm.active);
  EXPECT_EQ(board.alarms()[0].alarm.raised_at, 40);
  board.on_device_alarm(device_alarm(AlarmKind::kMayday, 40, false, 60), 540);
  EXPECT_EQ(board.active_count(), 0U);
}

TEST(AlarmBoard, SameAlarmTellsEveryField) {
  IncidentAlarm a;
  a.alarm_id = 4;
  a.alarm = device_alarm(AlarmKind::kMayday, 100, true);
  EXPECT_TRUE(same_alarm(a, a));
  auto b = a;
  b.alarm.last_position.covariance(1, 1) = 2.0;
  EXPECT_FALSE(same_alarm(a, b));
  b = a;
  b.acknowledged_by = "ic";
  EXPECT_FALSE(same_alarm(a, b));
  b = a;
  b.alarm.raised_at = 101;
  EXPECT_FALSE(same_alarm(a, b));
  b = a;
  b.alarm.floor = 1;
  EXPECT_FALSE(same_alarm(a, b));
}

TEST(AlarmBoard, RefusesAnEmptyResponderAndAClearBeforeItsRaise) {
  AlarmBoard board;
  auto a = device_alarm(AlarmKind::kMayday, 100, true);
  a.responder_id.clear();
  EXPECT_THROW(board.on_device_alarm(a, 1), InputError);
  EXPECT_THROW(board.on_device_alarm(device_alarm(AlarmKind::kMayday, 100, false, 50), 1), InputError);
  EXPECT_THROW(board.set_condition("", "t", AlarmKind::kLinkLost, true, 1), InputError);
  EXPECT_TRUE(board.alarms().empty());
}

}  // namespace
}  // namespace sarloc::incident
