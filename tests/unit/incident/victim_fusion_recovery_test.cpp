// VictimFusion and IncidentCommand when a FOUND victim is dug out: it stays where it was found,
// its signal is expected no more, and a signal still heard there is a new, unknown victim.
#include <gtest/gtest.h>

#include "incident_commands.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/incident_command.hpp"
#include "sarloc/core/incident/victim_fusion.hpp"
#include "source_estimates.hpp"

namespace sarloc::incident {
namespace {

using responder::EstimatorStatus;
using test::kSec;
using test::src;

const Vec3 kDigSite(10.0, 20.0, -1.5);

// r1 finds the victim at kDigSite; r2's converged estimate of it is bound too.
VictimFusion found_by_r1_heard_by_r2() {
  VictimFusion f;
  for (int k = 0; k < 3; ++k) {
    const TimestampNs t = k * kSec;
    f.update(src("r1", 1, t, kDigSite, 0.2, k == 0 ? EstimatorStatus::kConverged : EstimatorStatus::kFound));
    f.update(src("r2", 1, t, kDigSite + Vec3(0.4, 0.0, 0.0), 1.0));
    f.step(t);
  }
  return f;
}

std::string refusal(VictimFusion& f, std::uint32_t id) {
  try {
    f.recover(id);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(VictimRecovery, OnlyAFoundVictimIsDugOut) {
  VictimFusion f = found_by_r1_heard_by_r2();
  f.update(src("r3", 1, 2 * kSec, Vec3(60, 0, -1), 0.5, EstimatorStatus::kLocated));
  f.step(2 * kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  ASSERT_EQ(f.victims()[1].state, VictimState::kLocated);
  EXPECT_EQ(refusal(f, 9), "victim_recovery.victim_id = 9: no such victim");
  EXPECT_EQ(refusal(f, 2),
            "victim_recovery.victim_id = 2: the victim is LOCATED, not FOUND: only a found victim is dug out");
  EXPECT_EQ(f.victims()[1].state, VictimState::kLocated) << "a refused recovery changes nothing";
  EXPECT_EQ(f.retired_count(), 0u);
}

TEST(VictimRecovery, ADugOutVictimStaysWhereItWasFoundAndItsSignalsAreNotHeardAgain) {
  VictimFusion f = found_by_r1_heard_by_r2();
  ASSERT_EQ(f.victims().size(), 1u);
  ASSERT_EQ(f.victims()[0].state, VictimState::kFound);
  const FusedVictim before = f.victims()[0];
  EXPECT_TRUE(f.recover(1));
  EXPECT_FALSE(f.recover(1)) << "already dug out";
  EXPECT_EQ(f.retired_count(), 2u);
  // The finder's device republishes its FOUND, r2's filter still holds its last estimate.
  EXPECT_FALSE(f.update(src("r1", 1, 5 * kSec, kDigSite, 0.2, EstimatorStatus::kFound)));
  EXPECT_FALSE(f.update(src("r2", 1, 5 * kSec, kDigSite + Vec3(3.0, 0.0, 0.0), 1.0)));
  f.step(5 * kSec);
  f.step(30 * kSec);
  ASSERT_EQ(f.victims().size(), 1u);
  const FusedVictim& v = f.victims()[0];
  EXPECT_EQ(v.state, VictimState::kRecovered);
  EXPECT_TRUE(v.position.position.isApprox(before.position.position)) << "its final position";
  EXPECT_EQ(v.found_at, before.found_at);
  ASSERT_EQ(v.sources.size(), 2u) << "who found it stays listed";
  EXPECT_EQ(f.source_count(), 0u);
}

TEST(VictimRecovery, ASignalStillHeardWhereAVictimWasDugOutIsANewUnknownVictim) {
  VictimFusion f = found_by_r1_heard_by_r2();
  ASSERT_TRUE(f.recover(1));
  // Another transmitter 0.5 m away (a second victim under the first): r3 hears it, then r1's
  // device separates it as a new signal and stands over it.
  const Vec3 second = kDigSite + Vec3(0.5, 0.0, -0.5);
  f.update(src("r3", 1, 6 * kSec, second, 0.5));
  f.step(6 * kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kRecovered);
  EXPECT_EQ(f.victims()[1].victim_id, 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kUnconfirmed) << "new, and not confirmed by anything yet";
  EXPECT_EQ(f.victims()[1].possibly_same_as, 0u) << "never the dug-out one again";
  f.update(src("r1", 2, 8 * kSec, second, 0.2, EstimatorStatus::kFound));
  f.update(src("r3", 1, 8 * kSec, second, 0.5));
  f.step(8 * kSec);
  ASSERT_EQ(f.victims().size(), 2u) << "a recovered victim never merges";
  EXPECT_EQ(f.victims()[1].state, VictimState::kFound);
  EXPECT_EQ(f.victims()[1].sources.size(), 2u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kRecovered);
}

// A standby adopts the active one's recovered victim: its listed sources are retired there too.
TEST(VictimRecovery, AStandbyAdoptsADugOutVictimAndIgnoresItsSignals) {
  VictimFusion active = found_by_r1_heard_by_r2();
  ASSERT_TRUE(active.recover(1));
  VictimFusion standby;
  standby.update(src("r1", 1, 2 * kSec, kDigSite, 0.2, EstimatorStatus::kFound));
  standby.adopt(active.victims());
  EXPECT_EQ(standby.retired_count(), 2u);
  EXPECT_FALSE(standby.update(src("r2", 1, 9 * kSec, kDigSite, 1.0)));
  standby.step(9 * kSec);
  ASSERT_EQ(standby.victims().size(), 1u);
  EXPECT_EQ(standby.victims()[0].state, VictimState::kRecovered);
  // One that dug it out itself keeps it so when the active one's picture still says FOUND.
  VictimFusion ahead = found_by_r1_heard_by_r2();
  const std::vector<FusedVictim> still_found = ahead.victims();
  ahead.adopt(still_found);
  ASSERT_TRUE(ahead.recover(1));
  ahead.adopt(still_found);
  EXPECT_EQ(ahead.victims()[0].state, VictimState::kRecovered);
}

TEST(VictimRecovery, IncidentCommandKeepsADugOutVictimAndRefusesWhatItCannotDigOut) {
  auto config = test::command_config();
  IncidentCommand command(config, test::at(0));
  command.on_position(test::gnss_fix("r1", test::at(1), Vec3(40, 190, 0)), "w-r1", test::at(1));
  command.on_estimate(test::estimate_of("r1", 1, test::at(1), EstimatorStatus::kFound), "w-r1", true, test::at(1));
  auto out = command.cycle(test::at(1.5), test::at(1.5));
  ASSERT_EQ(out.victims.size(), 1u);
  ASSERT_EQ(out.victims[0].state, VictimState::kFound);
  const std::uint32_t id = out.victims[0].victim_id;

  command.on_recovery(id + 1, "dashboard");
  command.on_recovery(id, "bad id");
  out = command.cycle(test::at(2), test::at(2));
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kRejected, "no such victim"));
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kRejected, "reported_by is not an identifier"));
  ASSERT_EQ(out.victims[0].state, VictimState::kFound) << "refused: nothing changed";

  command.on_recovery(id, "dashboard");
  out = command.cycle(test::at(3), test::at(3));
  ASSERT_EQ(out.victims.size(), 1u);
  EXPECT_EQ(out.victims[0].state, VictimState::kRecovered);
  EXPECT_EQ(out.counts.victims_found, 1u) << "a recovered victim was found";
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kInfo, "dug out (reported by 'dashboard')"));
  // The finder's device still republishes its FOUND: nothing new opens.
  command.on_position(test::gnss_fix("r1", test::at(4), Vec3(40, 190, 0)), "w-r1", test::at(4));
  command.on_estimate(test::estimate_of("r1", 1, test::at(4), EstimatorStatus::kFound), "w-r1", true, test::at(4));
  out = command.cycle(test::at(5), test::at(5));
  ASSERT_EQ(out.victims.size(), 1u);
  EXPECT_EQ(out.victims[0].state, VictimState::kRecovered);
}

}  // namespace
}  // namespace sarloc::incident
