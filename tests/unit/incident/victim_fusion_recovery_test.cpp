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
const TimestampNs kDug = 3 * kSec;  // when the tests' victim is dug out

// `e` with a transmitter signature (carrier offset, pulse period) as a realistic receiver measures it.
SourceEstimate with_transmitter(SourceEstimate e, double carrier_hz, double period_s) {
  e.transmitter = responder::TransmitterSignature{carrier_hz, 4.6, period_s, 0.0002};
  return e;
}

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
    f.recover(id, kDug);
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
  EXPECT_TRUE(f.recover(1, kDug));
  EXPECT_FALSE(f.recover(1, kDug)) << "already dug out";
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
  ASSERT_TRUE(f.recover(1, kDug));
  // Another transmitter 0.5 m away (a second victim under the first): r3 first hears it after
  // the dig's grace, then r1's device separates it as a new signal and stands over it.
  const Vec3 second = kDigSite + Vec3(0.5, 0.0, -0.5);
  const TimestampNs heard = kDug + static_cast<TimestampNs>(f.config().dug_out_grace_s * 1e9) + kSec;
  f.update(src("r3", 1, heard, second, 0.5));
  f.step(heard);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kRecovered);
  EXPECT_EQ(f.victims()[1].victim_id, 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kUnconfirmed) << "new, and not confirmed by anything yet";
  EXPECT_EQ(f.victims()[1].possibly_same_as, 0u) << "never the dug-out one again";
  f.update(src("r1", 2, heard + 2 * kSec, second, 0.2, EstimatorStatus::kFound));
  f.update(src("r3", 1, heard + 2 * kSec, second, 0.5));
  f.step(heard + 2 * kSec);
  ASSERT_EQ(f.victims().size(), 2u) << "a recovered victim never merges";
  EXPECT_EQ(f.victims()[1].state, VictimState::kFound);
  EXPECT_EQ(f.victims()[1].sources.size(), 2u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kRecovered);
}

// The fade seen on large-deposit.yaml: the picture lost r3's source of the victim, the victim
// was dug out, and r3's FOUND of it (measured before the dig) came back afterwards.
TEST(VictimRecovery, ALateEstimateOfADugOutTransmitterIsRetiredWithItNotANewVictim) {
  VictimFusion f = found_by_r1_heard_by_r2();
  ASSERT_TRUE(f.recover(1, kDug));
  const Vec3 r3_found = kDigSite + Vec3(0.3, -0.2, 0.1);
  EXPECT_FALSE(f.update(src("r3", 1, kDug - kSec, r3_found, 0.2, EstimatorStatus::kFound)));
  f.step(kDug + 8 * kSec);
  // Its device republishes it, and measures on it a few pulses after the switch-off.
  EXPECT_FALSE(f.update(src("r3", 1, kDug + 12 * kSec, r3_found, 0.2, EstimatorStatus::kFound)));
  f.step(kDug + 12 * kSec);
  ASSERT_EQ(f.victims().size(), 1u) << "no second victim at the hole";
  EXPECT_EQ(f.victims()[0].state, VictimState::kRecovered);
  EXPECT_EQ(f.retired_count(), 3u);
  const auto echoes = f.take_late_echoes();
  ASSERT_EQ(echoes.size(), 1u) << "said once";
  EXPECT_EQ(echoes[0].victim_id, 1u);
  EXPECT_EQ(echoes[0].rescuer_id, "r3");
  EXPECT_EQ(echoes[0].measured, kDug - kSec);

  // The same when the late estimate arrived just before the recovery, in the same cycle.
  VictimFusion g = found_by_r1_heard_by_r2();
  EXPECT_TRUE(g.update(src("r3", 1, kDug, r3_found, 0.2, EstimatorStatus::kFound)));
  ASSERT_TRUE(g.recover(1, kDug));
  g.step(kDug + kSec);
  ASSERT_EQ(g.victims().size(), 1u);
  EXPECT_EQ(g.retired_count(), 3u);
  EXPECT_EQ(g.source_count(), 0u);
}

// What tells another transmitter at the hole from the dug-out one: a different signature, a
// place outside the gate or beyond kDugOutReachM, or first heard after the grace.
TEST(VictimRecovery, AnotherTransmitterHeardAtTheHoleBeforeTheDigIsKept) {
  auto dug_out_with_signature = [] {
    VictimFusion f;
    for (int k = 0; k < 3; ++k) {
      const TimestampNs t = k * kSec;
      const auto st = k == 0 ? EstimatorStatus::kConverged : EstimatorStatus::kFound;
      f.update(with_transmitter(src("r1", 1, t, kDigSite, 0.2, st), 12.0, 1.05));
      f.step(t);
    }
    EXPECT_TRUE(f.recover(1, kDug));
    return f;
  };
  struct Case {
    const char* what;
    SourceEstimate late;
  };
  const std::vector<Case> cases = {
      {"another carrier", with_transmitter(src("r3", 1, kDug - kSec, kDigSite + Vec3(0.3, 0, 0), 0.2), -40.0, 1.05)},
      {"confidently 1.5 m away", src("r3", 1, kDug - kSec, kDigSite + Vec3(1.5, 0, 0), 0.15)},
      {"beyond the reach", src("r3", 1, kDug - kSec, kDigSite + Vec3(kDugOutReachM + 0.5, 0, 0), 3.0)},
  };
  for (const Case& c : cases) {
    VictimFusion f = dug_out_with_signature();
    EXPECT_TRUE(f.update(c.late)) << c.what;
    f.step(kDug + 5 * kSec);
    ASSERT_EQ(f.victims().size(), 2u) << c.what << ": a new victim";
    EXPECT_EQ(f.victims()[1].sources.size(), 1u) << c.what;
  }
  // The dug-out transmitter's own signature, at the hole: its echo.
  VictimFusion f = dug_out_with_signature();
  EXPECT_FALSE(f.update(with_transmitter(src("r3", 1, kDug - kSec, kDigSite, 0.2), 10.0, 1.05)));
  f.step(kDug + 5 * kSec);
  EXPECT_EQ(f.victims().size(), 1u);
}

// A standby adopts the active one's recovered victim: its listed sources are retired there too.
TEST(VictimRecovery, AStandbyAdoptsADugOutVictimAndIgnoresItsSignals) {
  VictimFusion active = found_by_r1_heard_by_r2();
  ASSERT_TRUE(active.recover(1, kDug));
  VictimFusion standby;
  standby.update(src("r1", 1, 2 * kSec, kDigSite, 0.2, EstimatorStatus::kFound));
  standby.adopt(active.victims());
  EXPECT_EQ(standby.retired_count(), 2u);
  EXPECT_FALSE(standby.update(src("r2", 1, 9 * kSec, kDigSite, 1.0)));
  // A late estimate measured before the dig (its recovery not heard: the victim's newest
  // source stamp stands for it) is its echo there too.
  EXPECT_FALSE(standby.update(src("r3", 1, kSec, kDigSite, 0.2, EstimatorStatus::kFound)));
  standby.step(9 * kSec);
  ASSERT_EQ(standby.victims().size(), 1u);
  EXPECT_EQ(standby.victims()[0].state, VictimState::kRecovered);
  // One that dug it out itself keeps it so when the active one's picture still says FOUND.
  VictimFusion ahead = found_by_r1_heard_by_r2();
  const std::vector<FusedVictim> still_found = ahead.victims();
  ahead.adopt(still_found);
  ASSERT_TRUE(ahead.recover(1, kDug));
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

  command.on_recovery(id + 1, "dashboard", test::at(2), test::at(2));
  command.on_recovery(id, "bad id", test::at(2), test::at(2));
  out = command.cycle(test::at(2), test::at(2));
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kRejected, "no such victim"));
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kRejected, "reported_by is not an identifier"));
  ASSERT_EQ(out.victims[0].state, VictimState::kFound) << "refused: nothing changed";

  command.on_recovery(id, "dashboard", test::at(2.5), test::at(3));
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
  // r2's FOUND of it, measured before the dig, arrives after a fade: its late echo, said so.
  command.on_position(test::gnss_fix("r2", test::at(2), Vec3(40, 190, 0)), "w-r2", test::at(6));
  command.on_estimate(test::estimate_of("r2", 1, test::at(2), EstimatorStatus::kFound), "w-r2", true, test::at(6));
  out = command.cycle(test::at(6), test::at(6));
  ASSERT_EQ(out.victims.size(), 1u) << "no second victim at the hole";
  EXPECT_TRUE(test::has_event(out, IncidentEvent::Kind::kInfo, "'r2' signal 1: an estimate of dug-out victim"));
}

}  // namespace
}  // namespace sarloc::incident
