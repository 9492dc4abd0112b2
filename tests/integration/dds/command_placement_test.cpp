// Incident command places a victim estimate with the reporter's fix of the estimate's own
// epoch. A device's estimate carries that fix itself, so it is placed even when every
// responder_position of its epoch was lost (a long radio fade outlasting the positions'
// history: a FOUND estimate is republished with the stamp it was found at). An estimate
// without it and without a fix waits `command.fix_wait_s`, then is dropped, as before.
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

// Rescuer `id` at (10, 20) (GNSS) reports signal 1 three metres east and four north of it,
// FOUND; with or without carrying its own fix. No responder_position is ever published.
::sarloc::VictimEstimate found_estimate(const std::string& id, TimestampNs stamp, bool carries_fix) {
  responder::VictimEstimate e;
  e.rescuer_id = id;
  e.signal_id = 1;
  e.stamp = stamp;
  e.status = responder::EstimatorStatus::kFound;
  e.relative.position = Vec3(3.0, 4.0, -2.0);  // 1 m antenna height: 1 m below the snow
  e.relative.covariance = 0.01 * Mat3::Identity();
  if (carries_fix) {
    responder::ResponderPosition p;
    p.responder_id = id;
    p.team_id = "north";
    p.stamp = stamp;
    p.position.position = Vec3(10.0, 20.0, 1500.0);  // GNSS altitude: replaced by the antenna height
    p.position.covariance = 0.01 * Mat3::Identity();
    e.reporter = p;
  }
  auto message = to_idl(e, 1);
  message.from_device(true);
  return message;
}

TEST(CommandPlacement, ADeviceEstimateCarryingItsFixIsPlacedWithoutAnyResponderPosition) {
  const MissionClock clock;
  CommandNodeConfig config;
  config.node_id = "command-placement";
  config.incident.incident_id = "placement-test";
  config.cycle_s = 0.1;
  config.incident.fix_wait_s = 1.0;
  auto p = test::make_participant(test::kDomainCommandPlacement, "command");
  CommandNode command(p, config, clock);
  auto device = test::make_participant(test::kDomainCommandPlacement, "rescuers");
  Writer<::sarloc::VictimEstimate> estimates(device);
  ASSERT_TRUE(estimates.wait_for_readers(1, 10s));

  ASSERT_TRUE(estimates.write(found_estimate("r2", clock.now(), false)));
  ASSERT_TRUE(estimates.write(found_estimate("r1", clock.now(), true)));
  ASSERT_TRUE(eventually([&] { return command.victims().size() == 1; }, 5s));
  const incident::FusedVictim v = command.victims()[0];
  EXPECT_EQ(v.state, incident::VictimState::kFound);
  EXPECT_NEAR(v.position.position.x(), 13.0, 0.05);
  EXPECT_NEAR(v.position.position.y(), 24.0, 0.05);
  EXPECT_NEAR(v.position.position.z(), -1.0, 0.2) << "placed with the antenna height, not the GNSS altitude";
  ASSERT_EQ(v.sources.size(), 1U);
  EXPECT_EQ(v.sources[0].rescuer_id, "r1");
  // r2's estimate, without a fix of its own epoch anywhere, is never placed.
  std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(config.incident.fix_wait_s * 1000) + 500));
  EXPECT_EQ(command.victims().size(), 1U);
}

}  // namespace
}  // namespace sarloc::dds
