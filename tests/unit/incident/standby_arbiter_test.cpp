#include "sarloc/core/incident/standby_arbiter.hpp"

#include <gtest/gtest.h>

#include "sarloc/core/common/errors.hpp"
#include "support/config_messages.hpp"

namespace sarloc::incident {
namespace {

constexpr TimestampNs kSec = 1'000'000'000;
constexpr TimestampNs kStart = 1'763'800'000 * kSec;  // 2025-11-22, wall clock

StandbyConfig two(unsigned instance) {
  StandbyConfig c;
  c.instance = instance;
  c.instances = 2;
  return c;  // claim_wait_s 4, claim_stagger_s 1
}

TEST(StandbyArbiter, ConfigValidation) {
  EXPECT_NO_THROW(StandbyConfig{}.validate());
  StandbyConfig c;
  c.instances = 0;
  EXPECT_EQ(sarloc::test::validation_error(c), "command.instances = 0: must be in [1, 4]");
  c.instances = 5;
  EXPECT_EQ(sarloc::test::validation_error(c), "command.instances = 5: must be in [1, 4]");
  c = two(3);
  EXPECT_EQ(sarloc::test::validation_error(c), "--instance = 3: must be in [1, command.instances = 2]");
  c = two(1);
  c.claim_wait_s = -1.0;
  EXPECT_EQ(sarloc::test::validation_error(c), "command.claim_wait_s = -1: must be in [0, 600]");
  c = two(1);
  c.peer_period_s = 0.0;
  EXPECT_EQ(sarloc::test::validation_error(c), "command.cycle_s = 0: must be in (0, 60]");
  EXPECT_THROW(StandbyArbiter(c, kStart), ConfigError);
}

TEST(StandbyArbiter, ASingleInstanceIsActiveAtOnce) {
  StandbyArbiter a(StandbyConfig{}, kStart);
  EXPECT_EQ(a.role(), CommandRole::kStandby);
  EXPECT_EQ(a.strength(), 0U);
  const auto change = a.decide(kStart);
  ASSERT_TRUE(change);
  EXPECT_EQ(change->role, CommandRole::kActive);
  EXPECT_EQ(change->strength, StandbyArbiter::active_strength(kStart, 1));
  EXPECT_EQ(a.strength(), change->strength);
  EXPECT_FALSE(a.decide(kStart + kSec)) << "no change, no news";
}

// Both start together: instance 1 claims after claim_wait_s; instance 2 would claim a second
// later but hears instance 1's summary first and stays standby.
TEST(StandbyArbiter, AtStartTheFirstInstanceClaimsAndTheSecondStandsBy) {
  StandbyArbiter one(two(1), kStart);
  StandbyArbiter second(two(2), kStart);
  EXPECT_FALSE(one.decide(kStart + 3 * kSec));
  EXPECT_FALSE(second.decide(kStart + 3 * kSec));
  const auto change = one.decide(kStart + 4 * kSec);
  ASSERT_TRUE(change);
  EXPECT_EQ(change->role, CommandRole::kActive);
  for (TimestampNs t = 4; t < 60; ++t) {  // one summary a cycle (1 s)
    second.on_peer_sample("one", kStart + t * kSec + kSec / 10);
    EXPECT_FALSE(second.decide(kStart + (t + 1) * kSec));
  }
  EXPECT_EQ(second.role(), CommandRole::kStandby);
  EXPECT_TRUE(second.peer_active());
}

TEST(StandbyArbiter, TheStandbyTakesOverAtOnceWhenTheActiveIsLost) {
  StandbyArbiter s(two(2), kStart);
  for (TimestampNs t = 1; t <= 44; ++t) {
    s.on_peer_sample("one", kStart + t * kSec);
    EXPECT_FALSE(s.decide(kStart + t * kSec));
  }
  s.on_peer_lost("a standby that never wrote", kStart + 44 * kSec);
  EXPECT_FALSE(s.decide(kStart + 44 * kSec)) << "an unknown writer is not the active one";
  s.on_peer_lost("one", kStart + 45 * kSec);
  const auto change = s.decide(kStart + 45 * kSec);
  ASSERT_TRUE(change);
  EXPECT_EQ(change->role, CommandRole::kActive);
  EXPECT_EQ(change->reason, "the active instance was lost");
  EXPECT_EQ(change->strength, StandbyArbiter::active_strength(kStart + 45 * kSec, 2));
}

// The liveliness notice of the dead active instance never came (or a late sample of it re-added
// it): silent for claim_wait_s + 2 cycles, it is lost all the same. Before, the standby waited
// for the notice for good (a test-suite mission once ended with no standby taking over).
TEST(StandbyArbiter, TheStandbyTakesOverWhenTheActiveGoesSilentWithoutANotice) {
  StandbyConfig c = two(2);
  c.peer_period_s = 0.25;
  StandbyArbiter s(c, kStart);
  for (TimestampNs ms = 1000; ms <= 45000; ms += 250) {
    s.on_peer_sample("one", kStart + ms * 1'000'000);
    EXPECT_FALSE(s.decide(kStart + ms * 1'000'000 + 100'000'000));
  }
  // Last summary at 45 s: silent up to 4.5 s is still the lease's business.
  EXPECT_FALSE(s.decide(kStart + 49 * kSec + kSec / 2));
  const auto change = s.decide(kStart + 49 * kSec + kSec / 2 + kSec / 10);
  ASSERT_TRUE(change);
  EXPECT_EQ(change->role, CommandRole::kActive);
  EXPECT_EQ(change->reason, "the active instance was lost");
}

// A restarted instance hears the active one's TRANSIENT_LOCAL summary at discovery and never
// claims, whatever its instance number.
TEST(StandbyArbiter, ARestartedInstanceRejoinsAsStandby) {
  StandbyArbiter restarted(two(1), kStart + 100 * kSec);
  for (TimestampNs t = 100; t < 200; ++t) {
    restarted.on_peer_sample("two", kStart + t * kSec + kSec / 2);
    EXPECT_FALSE(restarted.decide(kStart + t * kSec + kSec / 2));
  }
  EXPECT_EQ(restarted.role(), CommandRole::kStandby);
  EXPECT_EQ(restarted.strength(), 0U);
}

// Two claimed (a restarted one did not hear the active one in time): the later one is weaker,
// so it receives the incumbent's samples, steps down, and takes over when that one is lost.
TEST(StandbyArbiter, TheLaterOfTwoActiveInstancesStepsDown) {
  StandbyArbiter late(two(1), kStart);
  ASSERT_TRUE(late.decide(kStart + 4 * kSec));
  late.on_peer_sample("incumbent", kStart + 5 * kSec);
  const auto down = late.decide(kStart + 5 * kSec);
  ASSERT_TRUE(down);
  EXPECT_EQ(down->role, CommandRole::kStandby);
  EXPECT_EQ(down->strength, 0U);
  for (TimestampNs t = 6; t <= 30; ++t) {
    late.on_peer_sample("incumbent", kStart + t * kSec);
    EXPECT_FALSE(late.decide(kStart + t * kSec));
  }
  late.on_peer_lost("incumbent", kStart + 31 * kSec);
  const auto up = late.decide(kStart + 31 * kSec);
  ASSERT_TRUE(up);
  EXPECT_EQ(up->role, CommandRole::kActive);
}

TEST(StandbyArbiter, EarlierActivationIsStrongerThenTheLowerInstance) {
  const auto s = [](TimestampNs t, unsigned i) { return StandbyArbiter::active_strength(t, i); };
  EXPECT_GT(s(kStart, 2), s(kStart + kSec, 1)) << "the incumbent outranks a later claim";
  EXPECT_GT(s(kStart, 1), s(kStart, 2));
  EXPECT_GT(s(kStart + kSec / 2, 4), s(kStart + kSec, 1));
  EXPECT_EQ(s(0, 1), 2'000'000'000U);                  // before 2025: the ceiling
  EXPECT_GE(s(kStart + 1'000'000'000 * kSec, 4), 1U);  // far future: never 0 (a standby's)
  EXPECT_LE(s(kStart, 1), 2'147'483'647U) << "an int32 for other vendors";
}

}  // namespace
}  // namespace sarloc::incident
