// Incident command's alarm board: an alarm stays until it is acknowledged and cleared, a device's
// raise and clear are one alarm in any order, conditions open one alarm per episode, and a standby
// adopts the active board with its ids.
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
  EXPECT_EQ(board.acknowledge(id, "ic", 102), AckResult::kAcknowledged);
  EXPECT_EQ(board.acknowledge(id, "ic", 103), AckResult::kAlready);
  ASSERT_EQ(board.alarms().size(), 1U) << "acknowledged but still active: stays";
  EXPECT_TRUE(board.alarms()[0].acknowledged);
  EXPECT_TRUE(board.take_removed().empty());
  board.on_device_alarm(device_alarm(AlarmKind::kMotionless, 100, false, 150), 151);
  EXPECT_TRUE(board.alarms().empty()) << "acknowledged and cleared: gone";
  EXPECT_EQ(board.take_removed(), std::vector<std::uint32_t>{id});
  EXPECT_EQ(board.acknowledge(id, "ic", 160), AckResult::kUnknown);
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
  // A new raise of the same kind is a new alarm.
  board.on_device_alarm(device_alarm(AlarmKind::kMotionless, 300, true), 301);
  EXPECT_EQ(board.alarms().size(), 3U);
  EXPECT_EQ(board.active_count(), 1U);
}

TEST(AlarmBoard, ConditionsOpenOneAlarmPerEpisode) {
  AlarmBoard board;
  for (TimestampNs t = 0; t < 5; ++t) board.set_condition("ff1", "alpha", AlarmKind::kLinkLost, true, 10 + t);
  ASSERT_EQ(board.alarms().size(), 1U);
  EXPECT_EQ(board.alarms()[0].alarm.raised_at, 10);
  board.set_condition("ff1", "alpha", AlarmKind::kLinkLost, false, 20);
  board.set_condition("ff1", "alpha", AlarmKind::kLinkLost, false, 21);
  board.set_condition("ff1", "alpha", AlarmKind::kLinkLost, true, 30, GaussianPosition{}, 2);
  ASSERT_EQ(board.alarms().size(), 2U) << "the first, cleared and unacknowledged, and a second episode";
  EXPECT_EQ(board.alarms()[0].alarm.cleared_at, 20);
  EXPECT_TRUE(board.alarms()[1].alarm.active);
  EXPECT_TRUE(board.alarms()[1].alarm.position_known);
  EXPECT_EQ(board.alarms()[1].alarm.floor, 2);
  EXPECT_EQ(board.acknowledge(board.alarms()[0].alarm_id, "ic", 40), AckResult::kAcknowledged);
  EXPECT_EQ(board.alarms().size(), 1U);
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
