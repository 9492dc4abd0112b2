// Two incident-command nodes in hot standby, each on its own participant (as two processes
// would be): one claims the picture, the other adopts it, and takes over with the same victim
// ids when the first one leaves. (A SIGKILLed instance, found out by the 3 s lease, is tested
// by the mission tests.)
#include <gtest/gtest.h>

#include <map>
#include <mutex>

#include "sarloc/dds/command_node.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"
#include "support/sample_messages.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;
using test::eventually;

CommandNodeConfig instance(unsigned k) {
  CommandNodeConfig c;
  c.node_id = "command-" + std::to_string(k);
  c.incident.incident_id = "standby-test";
  c.cycle_s = 0.1;
  c.incident.standby.instance = k;
  c.incident.standby.instances = 2;
  c.incident.standby.claim_wait_s = 0.5;
  return c;
}

// Rescuer r1 at the origin (GNSS) reports signal 1 four metres north-east of it.
void report(Writer<::sarloc::ResponderPosition>& positions, Writer<::sarloc::VictimEstimate>& estimates,
            TimestampNs stamp, responder::EstimatorStatus status) {
  responder::ResponderPosition p;
  p.responder_id = "r1";
  p.team_id = "north";
  p.stamp = stamp;
  p.position.covariance = 0.01 * Mat3::Identity();
  ASSERT_TRUE(positions.write(to_idl(p)));
  responder::VictimEstimate e;
  e.rescuer_id = "r1";
  e.signal_id = 1;
  e.stamp = stamp;
  e.status = status;
  e.relative.position = Vec3(3.0, 4.0, -2.0);  // 1 m antenna height: 1 m below the snow
  e.relative.covariance = 0.01 * Mat3::Identity();
  auto message = to_idl(e, 1);
  message.from_device(true);  // the rescuer's own estimate: it may confirm (VictimFusion)
  ASSERT_TRUE(estimates.write(message));
}

TEST(CommandStandby, TheStandbyAdoptsThePictureAndTakesOverWithTheSameIds) {
  const MissionClock clock;  // the wall clock
  auto p1 = test::make_participant(test::kDomainCommandStandby, "command-1");
  auto p2 = test::make_participant(test::kDomainCommandStandby, "command-2");
  auto first = std::make_unique<CommandNode>(p1, instance(1), clock);
  CommandNode second(p2, instance(2), clock);
  ASSERT_TRUE(eventually([&] { return first->role() == incident::CommandRole::kActive; }, 5s));
  std::this_thread::sleep_for(2s);  // past the second one's claim wait (0.5 s + 1 s)
  EXPECT_EQ(second.role(), incident::CommandRole::kStandby) << "two active instances";

  auto device = test::make_participant(test::kDomainCommandStandby, "rescuer");
  Writer<::sarloc::ResponderPosition> positions(device);
  Writer<::sarloc::VictimEstimate> estimates(device);
  // Discovery on a loaded 2-core machine (every DDS test at once) once took more than 10 s.
  ASSERT_TRUE(positions.wait_for_readers(2, 30s));
  ASSERT_TRUE(estimates.wait_for_readers(2, 30s));
  report(positions, estimates, clock.now(), responder::EstimatorStatus::kLocated);
  ASSERT_TRUE(eventually([&] { return first->victims().size() == 1 && second.victims().size() == 1; }, 5s));
  ASSERT_TRUE(eventually([&] { return second.victims()[0].located_at == first->victims()[0].located_at; }, 5s));
  const incident::FusedVictim before = first->victims()[0];
  EXPECT_EQ(before.state, incident::VictimState::kLocated);
  EXPECT_EQ(second.victims()[0].victim_id, before.victim_id);

  first.reset();  // leaves: its writers unmatch at once
  p1.reset();
  ASSERT_TRUE(eventually([&] { return second.role() == incident::CommandRole::kActive; }, 5s));
  report(positions, estimates, clock.now(), responder::EstimatorStatus::kFound);
  ASSERT_TRUE(eventually(
      [&] {
        const auto v = second.victims();
        return v.size() == 1 && v[0].state == incident::VictimState::kFound;
      },
      5s));
  const incident::FusedVictim after = second.victims()[0];
  EXPECT_EQ(after.victim_id, before.victim_id);
  EXPECT_EQ(after.first_seen, before.first_seen);
  EXPECT_EQ(after.located_at, before.located_at);
  EXPECT_GT(after.found_at, before.located_at);
}

// Whoever takes over disposes again every victim id it knows of that its picture no longer
// holds, although it never wrote them: a reader may have missed the predecessor's disposal (a
// fade just before a hand-over), and may hold a victim the new active instance could not adopt.
// Here victim 2 is the latter (a covariance the standby rejects): the dashboard holds it, the
// standby knows its id from victim 3.
TEST(CommandStandby, TheNewActiveDisposesOfEveryVictimItsPictureNoLongerHolds) {
  const MissionClock clock;
  auto dashboard = test::make_participant(test::kDomainCommandRedispose, "dashboard");
  std::mutex mutex;
  std::map<eprosima::fastrtps::rtps::InstanceHandle_t, std::uint32_t> ids;
  std::vector<std::uint32_t> disposed;
  ReaderEvents events;
  events.on_instance_gone = [&](const auto& info) {
    if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
    std::lock_guard<std::mutex> lock(mutex);
    const auto it = ids.find(info.instance_handle);
    disposed.push_back(it == ids.end() ? 0U : it->second);
  };
  Reader<::sarloc::FusedVictim> picture(
      dashboard,
      [&](const ::sarloc::FusedVictim& v, const auto& info) {
        std::lock_guard<std::mutex> lock(mutex);
        ids[info.instance_handle] = v.victim_id();
      },
      {}, events);

  // The predecessor: an active instance's picture writers, stronger than any standby. It stops
  // asserting liveliness without leaving, as a killed or faded instance does.
  auto predecessor = test::make_participant(test::kDomainCommandRedispose, "command-1");
  Writer<::sarloc::IncidentSummary> summaries(predecessor);
  Writer<::sarloc::FusedVictim> victims(predecessor);
  const auto strength = incident::StandbyArbiter::active_strength(MissionClock::wall_now_ns(), 1);
  summaries.set_ownership_strength(strength);
  victims.set_ownership_strength(strength);
  CommandNode standby(test::make_participant(test::kDomainCommandRedispose, "command-2"), instance(2), clock);
  ASSERT_TRUE(victims.wait_for_readers(2, 10s));
  ASSERT_TRUE(summaries.wait_for_readers(1, 10s));
  auto victim = [](std::uint32_t id, bool adoptable) {
    auto v = test::sample_fused_victim();
    v.victim_id = id;
    v.possibly_same_as = 0;
    v.position.position = Vec3(20.0 * id, 0.0, -1.0);  // apart: nothing to merge
    for (auto& source : v.sources) source.signal_id += 10 * id;
    v.position.covariance = 0.04 * Mat3::Identity();
    if (!adoptable) v.position.covariance(0, 1) = 0.01;
    return to_idl(v);
  };
  ::sarloc::IncidentSummary summary;
  summary.incident_id("standby-test");
  for (int cycle = 0; cycle < 10; ++cycle) {  // 1 s of an active instance's cycles
    ASSERT_TRUE(victims.write(victim(1, true)));
    ASSERT_TRUE(victims.write(victim(2, false)));
    ASSERT_TRUE(victims.write(victim(3, true)));
    ASSERT_TRUE(summaries.write(summary));
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(standby.role(), incident::CommandRole::kStandby);
  {
    std::lock_guard<std::mutex> lock(mutex);
    ASSERT_EQ(ids.size(), 3U) << "the dashboard did not get the predecessor's picture";
    ASSERT_TRUE(disposed.empty());
  }
  ASSERT_TRUE(eventually([&] { return standby.role() == incident::CommandRole::kActive; }, 10s));
  ASSERT_TRUE(eventually(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return !disposed.empty();
      },
      10s))
      << "the new active instance did not dispose of victim 2";
  std::this_thread::sleep_for(500ms);
  std::lock_guard<std::mutex> lock(mutex);
  EXPECT_EQ(disposed, std::vector<std::uint32_t>{2U}) << "disposed of a victim still in the picture";
}

}  // namespace
}  // namespace sarloc::dds
