// Two incident-command nodes in hot standby, each on its own participant (as two processes
// would be): one claims the picture, the other adopts it, and takes over with the same victim
// ids when the first one leaves. (A SIGKILLed instance, found out by the 3 s lease, is tested
// by the mission tests.)
#include <gtest/gtest.h>

#include "sarloc/dds/command_node.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/writer.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;
using test::eventually;

CommandNodeConfig instance(unsigned k) {
  CommandNodeConfig c;
  c.node_id = "command-" + std::to_string(k);
  c.incident_id = "standby-test";
  c.cycle_s = 0.1;
  c.standby.instance = k;
  c.standby.instances = 2;
  c.standby.claim_wait_s = 0.5;
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
  ASSERT_TRUE(positions.wait_for_readers(2, 10s));
  ASSERT_TRUE(estimates.wait_for_readers(2, 10s));
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

}  // namespace
}  // namespace sarloc::dds
