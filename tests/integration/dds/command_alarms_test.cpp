// Incident command's alarms over DDS: a device's motionless alarm and a map-aided position
// flagged map error enter the picture as IncidentAlarms; an acknowledgement of an active alarm
// keeps it until it clears, an alarm cleared but unacknowledged stays, and acknowledged and
// cleared it is disposed. An acknowledgement of an unknown alarm is counted, nothing else. A map
// error that comes back before anyone answered reopens its alarm, and the dashboard's
// acknowledgement of an alarm that is gone goes too.
#include <gtest/gtest.h>

#include <map>
#include <mutex>
#include <set>

#include "sarloc/dds/command_node.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/dashboard_node.hpp"
#include "sarloc/dds/writer.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;
using test::eventually;

// Incident command cycling every 0.1 s, so that alarms follow their conditions within the waits.
CommandNodeConfig quick_command(const std::string& node_id, const std::string& incident_id) {
  CommandNodeConfig config;
  config.node_id = node_id;
  config.incident.incident_id = incident_id;
  config.cycle_s = 0.1;
  return config;
}

TEST(CommandAlarms, AlarmsStayUntilAcknowledgedAndClearedThenAreDisposed) {
  const MissionClock clock;
  const auto config = quick_command("command-alarms", "alarms-test");
  auto p = test::make_participant(test::kDomainCommandAlarms, "command");
  CommandNode command(p, config, clock);

  auto device = test::make_participant(test::kDomainCommandAlarms, "ff1");
  Writer<::sarloc::ResponderAlarm> alarms(device);
  Writer<::sarloc::ResponderPosition> positions(device);
  Writer<::sarloc::AlarmAcknowledgement> acks(device);
  std::mutex mutex;
  std::map<std::uint32_t, incident::IncidentAlarm> picture;
  std::set<std::uint32_t> disposed;
  ReaderEvents events;
  events.on_instance_gone = [&](const auto& info) {
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    if (const auto id = alarm_id_of(info.instance_handle)) {
      std::lock_guard<std::mutex> lock(mutex);
      disposed.insert(*id);
      picture.erase(*id);
    }
  };
  Reader<::sarloc::IncidentAlarm> reader(
      device,
      [&](const ::sarloc::IncidentAlarm& a, const auto&) {
        std::lock_guard<std::mutex> lock(mutex);
        picture[a.alarm_id()] = to_core(a);
      },
      EndpointOptions{}, events);
  ASSERT_TRUE(alarms.wait_for_readers(1, 10s));
  ASSERT_TRUE(acks.wait_for_readers(1, 10s));
  ASSERT_TRUE(reader.wait_for_writers(1, 10s));
  const auto find = [&](responder::AlarmKind kind) -> std::optional<incident::IncidentAlarm> {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& [id, a] : picture) {
      if (a.alarm.kind == kind && a.alarm.responder_id == "ff1") return a;
    }
    return std::nullopt;
  };

  // The device raises its motionless alarm; the daemon's map-aided position says map error.
  responder::ResponderAlarm motionless;
  motionless.responder_id = "ff1";
  motionless.team_id = "alpha";
  motionless.kind = responder::AlarmKind::kMotionless;
  motionless.raised_at = clock.now();
  motionless.active = true;
  ASSERT_TRUE(alarms.write(to_idl(motionless)));
  responder::ResponderPosition fix;
  fix.responder_id = "ff1";
  fix.team_id = "alpha";
  fix.stamp = clock.now();
  fix.position.covariance = 0.2 * Mat3::Identity();
  fix.floor = 1;
  fix.source = responder::PositionSource::kMapAided;
  fix.map_error_suspected = true;
  ASSERT_TRUE(positions.write(to_idl(fix)));
  ASSERT_TRUE(eventually([&] { return find(responder::AlarmKind::kMotionless) && find(responder::AlarmKind::kMapError); }, 5s));
  EXPECT_EQ(find(responder::AlarmKind::kMapError)->alarm.floor, 1);

  // Acknowledged while active: it stays, marked.
  const auto id = find(responder::AlarmKind::kMotionless)->alarm_id;
  ::sarloc::AlarmAcknowledgement ack;
  ack.alarm_id(id);
  ack.operator_id("ic-chief");
  ack.stamp(clock.now());
  ASSERT_TRUE(acks.write(ack));
  ASSERT_TRUE(eventually([&] { return find(responder::AlarmKind::kMotionless)->acknowledged; }, 5s));
  EXPECT_EQ(find(responder::AlarmKind::kMotionless)->acknowledged_by, "ic-chief");

  // The map error clears without an acknowledgement: it stays, cleared.
  fix.stamp = clock.now();
  fix.map_error_suspected = false;
  ASSERT_TRUE(positions.write(to_idl(fix)));
  ASSERT_TRUE(eventually([&] { return !find(responder::AlarmKind::kMapError)->alarm.active; }, 5s));

  // The firefighter moves again: acknowledged and cleared, the motionless alarm is disposed.
  motionless.active = false;
  motionless.cleared_at = clock.now();
  ASSERT_TRUE(alarms.write(to_idl(motionless)));
  ASSERT_TRUE(eventually([&] {
    std::lock_guard<std::mutex> lock(mutex);
    return disposed.count(id) == 1;
  }, 5s));
  EXPECT_TRUE(find(responder::AlarmKind::kMapError)) << "cleared, not acknowledged: still shown";

  // An unknown alarm id changes nothing.
  ack.alarm_id(9999);
  ASSERT_TRUE(acks.write(ack));
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(command.alarms().size(), 1U);
}

TEST(CommandAlarms, AMapErrorThatComesBackReopensItsAlarmAndTheAnswerGoesWithIt) {
  const MissionClock clock;
  CommandNode command(test::make_participant(test::kDomainCommandAlarmsReopen, "command"),
                      quick_command("command-reopen", "reopen-test"), clock);

  std::mutex mutex;
  std::map<std::uint32_t, incident::IncidentAlarm> picture;
  std::set<std::uint32_t> gone;
  DashboardSink sink;
  sink.on_alarm = [&](const incident::IncidentAlarm& a) {
    std::lock_guard<std::mutex> lock(mutex);
    picture[a.alarm_id] = a;
  };
  sink.on_alarm_gone = [&](std::uint32_t id) {
    std::lock_guard<std::mutex> lock(mutex);
    gone.insert(id);
    picture.erase(id);
  };
  DashboardNode dashboard(test::make_participant(test::kDomainCommandAlarmsReopen, "dashboard"), std::move(sink));

  auto device = test::make_participant(test::kDomainCommandAlarmsReopen, "ff1");
  Writer<::sarloc::ResponderPosition> positions(device);
  // Whoever else reads the acknowledgements (a standby, the recorder): which ones are held.
  std::set<std::uint32_t> acknowledged, acknowledgements_disposed;
  std::map<eprosima::fastrtps::rtps::InstanceHandle_t, std::uint32_t> ack_of_instance;
  ReaderEvents ack_events;
  ack_events.on_instance_gone = [&](const auto& info) {
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = ack_of_instance.find(info.instance_handle); it != ack_of_instance.end()) {
      acknowledgements_disposed.insert(it->second);
    }
  };
  Reader<::sarloc::AlarmAcknowledgement> acks(
      device,
      [&](const ::sarloc::AlarmAcknowledgement& a, const auto& info) {
        std::lock_guard<std::mutex> lock(mutex);
        acknowledged.insert(a.alarm_id());
        ack_of_instance[info.instance_handle] = a.alarm_id();
      },
      EndpointOptions{}, ack_events);
  ASSERT_TRUE(positions.wait_for_readers(1, 10s));
  const auto map_errors = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    std::vector<incident::IncidentAlarm> out;
    for (const auto& [id, a] : picture) {
      if (a.alarm.kind == responder::AlarmKind::kMapError) out.push_back(a);
    }
    return out;
  };
  responder::ResponderPosition fix;
  fix.responder_id = "ff1";
  fix.team_id = "alpha";
  fix.position.covariance = 0.2 * Mat3::Identity();
  fix.source = responder::PositionSource::kMapAided;
  const auto suspect = [&](bool suspected) {
    fix.stamp = clock.now();
    fix.map_error_suspected = suspected;
    ASSERT_TRUE(positions.write(to_idl(fix)));
  };

  suspect(true);
  ASSERT_TRUE(eventually([&] { return map_errors().size() == 1 && map_errors()[0].alarm.active; }, 5s));
  const auto id = map_errors()[0].alarm_id;
  const auto first_raise = map_errors()[0].alarm.raised_at;
  suspect(false);
  ASSERT_TRUE(eventually([&] { return !map_errors()[0].alarm.active; }, 5s));
  suspect(true);
  ASSERT_TRUE(eventually([&] { return map_errors()[0].alarm.active; }, 5s));
  ASSERT_EQ(map_errors().size(), 1U) << "nobody answered the first: the same alarm, again";
  EXPECT_EQ(map_errors()[0].alarm_id, id);
  EXPECT_GT(map_errors()[0].alarm.raised_at, first_raise);

  // Answered while active, then cleared: the alarm goes, and the dashboard's answer with it.
  ASSERT_TRUE(dashboard.acknowledge(id, "ic-chief", clock.now()));
  ASSERT_TRUE(eventually([&] { return map_errors()[0].acknowledged; }, 5s));
  ASSERT_TRUE(eventually(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return acknowledged.count(id) == 1;
      },
      5s));
  {
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_TRUE(acknowledgements_disposed.empty()) << "the alarm is still active";
  }
  suspect(false);
  ASSERT_TRUE(eventually(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return gone.count(id) == 1 && acknowledgements_disposed.count(id) == 1;
      },
      5s));
  // The next episode is a new alarm.
  suspect(true);
  ASSERT_TRUE(eventually([&] { return map_errors().size() == 1 && map_errors()[0].alarm.active; }, 5s));
  EXPECT_GT(map_errors()[0].alarm_id, id);
  EXPECT_FALSE(map_errors()[0].acknowledged);
}

}  // namespace
}  // namespace sarloc::dds
