// VictimFusion::adopt: a hot-standby incident command takes over the active one's picture.
#include <gtest/gtest.h>

#include <cmath>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/victim_fusion.hpp"
#include "source_estimates.hpp"

namespace sarloc::incident {
namespace {

using responder::EstimatorStatus;
using test::kSec;
using test::src;

void expect_same_victims(const std::vector<FusedVictim>& a, const std::vector<FusedVictim>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE("victim " + std::to_string(a[i].victim_id));
    EXPECT_EQ(a[i].victim_id, b[i].victim_id);
    EXPECT_EQ(a[i].state, b[i].state);
    EXPECT_EQ(a[i].first_seen, b[i].first_seen);
    EXPECT_EQ(a[i].located_at, b[i].located_at);
    EXPECT_EQ(a[i].found_at, b[i].found_at);
    EXPECT_EQ(a[i].floor, b[i].floor);
    EXPECT_EQ(a[i].evidence_conflict, b[i].evidence_conflict);
    EXPECT_LT((a[i].position.position - b[i].position.position).norm(), 1e-9);
    ASSERT_EQ(a[i].sources.size(), b[i].sources.size());
    for (std::size_t k = 0; k < a[i].sources.size(); ++k) {
      EXPECT_EQ(a[i].sources[k].rescuer_id, b[i].sources[k].rescuer_id);
      EXPECT_EQ(a[i].sources[k].signal_id, b[i].sources[k].signal_id);
    }
  }
}

// Feeds both fusions the same estimate (the standby reads the same topics).
void update_both(VictimFusion& active, VictimFusion& standby, const SourceEstimate& e) {
  active.update(e);
  standby.update(e);
}

// The active instance's history: victims 1 (a/1 + b/1, LOCATED) and 2 (c/2), and victim 3,
// opened by d/1 and then merged into 1 (disposed): ids 1, 2 remain, 3 was used.
void run_history(VictimFusion& active, VictimFusion& standby) {
  update_both(active, standby, src("a", 1, 1 * kSec, Vec3(0, 0, -1), 0.5, EstimatorStatus::kLocated));
  update_both(active, standby, src("c", 2, 1 * kSec, Vec3(30, 0, -1), 0.5));
  update_both(active, standby, src("d", 1, 1 * kSec, Vec3(8, 0, -1), 0.5));
  active.step(1 * kSec);
  standby.adopt(active.victims());  // a standby cycle: adopt the new picture, then step
  standby.step(1 * kSec);
  ASSERT_EQ(active.victims().size(), 3U);
  update_both(active, standby, src("b", 1, 2 * kSec, Vec3(0.2, 0, -1), 0.5));
  update_both(active, standby, src("d", 1, 2 * kSec, Vec3(0.4, 0, -1), 0.5));  // d moves onto victim 1
  update_both(active, standby, src("a", 1, 2 * kSec, Vec3(0, 0, -1), 0.5, EstimatorStatus::kLocated));
  update_both(active, standby, src("c", 2, 2 * kSec, Vec3(30, 0, -1), 0.5));
  active.step(2 * kSec);
  ASSERT_EQ(active.take_removed(), (std::vector<std::uint32_t>{3}));
  ASSERT_EQ(active.victims().size(), 2U);
  standby.adopt(active.victims(), /*largest_id_seen=*/3);
  standby.step(2 * kSec);
  EXPECT_TRUE(standby.take_removed().empty()) << "a standby's removals are not published anyway";
}

TEST(VictimFusionAdopt, TheStandbyContinuesExactlyAsTheActiveWould) {
  VictimFusion active;
  VictimFusion standby;
  run_history(active, standby);
  expect_same_victims(standby.victims(), active.victims());
  EXPECT_EQ(standby.next_id(), 4U) << "id 3 was disposed of: never reused";

  // The active instance dies here. Both continue with the same estimates: the standby's
  // picture is the one the active instance would have published.
  VictimFusion& successor = standby;
  for (TimestampNs t = 3 * kSec; t <= 6 * kSec; t += kSec) {
    const auto found = t >= 5 * kSec ? EstimatorStatus::kFound : EstimatorStatus::kLocated;
    update_both(active, successor, src("a", 1, t, Vec3(0, 0, -1), 0.3, found));
    update_both(active, successor, src("b", 1, t, Vec3(0.1, 0, -1), 0.5));
    update_both(active, successor, src("c", 2, t, Vec3(30, 0.1, -1), 0.5));
    update_both(active, successor, src("d", 1, t, Vec3(0.3, 0, -1), 0.5));
    active.step(t);
    successor.step(t);
    expect_same_victims(successor.victims(), active.victims());
  }
  ASSERT_EQ(successor.victims().size(), 2U);
  EXPECT_EQ(successor.victims()[0].victim_id, 1U);
  EXPECT_EQ(successor.victims()[0].state, VictimState::kFound);
  EXPECT_EQ(successor.victims()[0].located_at, 1 * kSec) << "set by the active instance, kept";
  EXPECT_EQ(successor.victims()[0].found_at, 5 * kSec);
  EXPECT_EQ(successor.victims()[0].first_seen, 1 * kSec);
  EXPECT_TRUE(successor.take_removed().empty());

  // A new victim after the handover gets the next unused id.
  successor.update(src("e", 3, 7 * kSec, Vec3(-40, 0, -1), 0.5));
  successor.step(7 * kSec);
  ASSERT_EQ(successor.victims().size(), 3U);
  EXPECT_EQ(successor.victims()[2].victim_id, 4U);
}

TEST(VictimFusionAdopt, TakesThePictureVerbatimWithoutFusing) {
  FusedVictim v;
  v.victim_id = 7;
  v.position.position = Vec3(1, 2, -1);
  v.position.covariance = 0.04 * Mat3::Identity();
  v.floor = 2;
  v.state = VictimState::kFound;
  v.first_seen = 10 * kSec;
  v.last_update = 12 * kSec;
  v.located_at = 11 * kSec;
  v.found_at = 12 * kSec;
  v.evidence_conflict = true;
  v.sources = {{"r1", 1, 12 * kSec}};
  VictimFusion f;
  auto e = src("r1", 1, 13 * kSec, Vec3(5, 5, -1), 0.5);  // the standby's own copy says elsewhere
  e.floor = 2;
  f.update(e);
  f.adopt({v});
  f.adopt({v});  // every standby cycle: idempotent
  ASSERT_EQ(f.victims().size(), 1U);
  expect_same_victims(f.victims(), {v});
  EXPECT_EQ(f.victims()[0].sources[0].last_update, 12 * kSec) << "as published";
  EXPECT_EQ(f.next_id(), 8U);
}

TEST(VictimFusionAdopt, ASourceHeardOnlyAfterTheAdoptionJoinsItsVictim) {
  FusedVictim v;
  v.victim_id = 3;
  v.position.position = Vec3(0, 0, -1);
  v.position.covariance = 0.25 * Mat3::Identity();
  v.state = VictimState::kLocated;
  v.located_at = 4 * kSec;
  v.sources = {{"late", 2, 4 * kSec}};
  VictimFusion f;  // a restarted standby: nothing heard yet
  f.adopt({v});
  // The TRANSIENT_LOCAL estimate arrives after the picture.
  f.update(src("late", 2, 5 * kSec, Vec3(0.2, 0, -1), 0.5));
  f.step(5 * kSec);
  ASSERT_EQ(f.victims().size(), 1U) << "the source opened a victim of its own";
  EXPECT_EQ(f.victims()[0].victim_id, 3U);
  ASSERT_EQ(f.victims()[0].sources.size(), 1U);
  EXPECT_EQ(f.victims()[0].sources[0].rescuer_id, "late");
  EXPECT_EQ(f.victims()[0].located_at, 4 * kSec);
}

TEST(VictimFusionAdopt, RefusesABadPictureAndKeepsItsOwn) {
  VictimFusion f;
  f.update(src("a", 1, kSec, Vec3(0, 0, -1), 0.5));
  f.step(kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  FusedVictim good;
  good.victim_id = 5;
  good.position.covariance = Mat3::Identity();
  FusedVictim bad = good;
  bad.position.position.x() = std::nan("");
  EXPECT_THROW(f.adopt({good, bad}), InputError);
  bad = good;
  bad.victim_id = 0;
  EXPECT_THROW(f.adopt({bad}), InputError);
  bad = good;
  bad.position.covariance(0, 0) = -1.0;
  EXPECT_THROW(f.adopt({bad}), InputError);
  EXPECT_THROW(f.adopt({good, good}), InputError);  // an id twice
  ASSERT_EQ(f.victims().size(), 1U);
  EXPECT_EQ(f.victims()[0].victim_id, 1U);
  try {
    bad = good;
    bad.sources = {{"", 1, 0}};
    check_adoptable(bad);
    FAIL() << "an empty rescuer id accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "fused_victim[5].sources.rescuer_id = \"\": must not be empty");
  }
}

// A standby adopts each new picture and steps every cycle, as incident command's node does.
// The active instance dies after publishing victim 1 LOCATED: no new picture comes, and until
// the standby notices (the 3 s lease) it fuses on its own from the last one. A FOUND heard in
// between, and a victim opened in between, are not lost, even once their sources time out.
TEST(VictimFusionAdopt, WhatTheStandbyFusedAfterTheLastPictureIsKept) {
  VictimFusion active;
  VictimFusion standby;
  update_both(active, standby, src("a", 1, 1 * kSec, Vec3(0, 0, -1), 0.5, EstimatorStatus::kLocated));
  active.step(1 * kSec);
  const std::vector<FusedVictim> last_picture = active.victims();  // then it dies
  ASSERT_EQ(last_picture.size(), 1U);
  standby.adopt(last_picture);
  standby.step(1 * kSec);

  standby.update(src("a", 1, 2 * kSec, Vec3(0, 0, -1), 0.3, EstimatorStatus::kFound));
  standby.update(src("z", 1, 2 * kSec, Vec3(50, 0, -1), 0.5));  // a victim the active one never saw
  standby.step(2 * kSec);
  standby.step(20 * kSec);  // sources timed out (10 s) by the time it takes over
  ASSERT_EQ(standby.victims().size(), 2U);
  EXPECT_EQ(standby.victims()[0].victim_id, 1U);
  EXPECT_EQ(standby.victims()[0].state, VictimState::kFound);
  EXPECT_EQ(standby.victims()[0].located_at, 1 * kSec) << "as published";
  EXPECT_EQ(standby.victims()[0].found_at, 2 * kSec) << "when the standby fused it";
  EXPECT_EQ(standby.victims()[1].victim_id, 2U);
}

// The active instance is alive but a cycle behind the standby: the standby's own progress on
// an adopted victim survives the next adoption (states never go back), a victim the standby
// opened itself gives way to the picture (which has it, or will), and the picture's own
// timestamps win once it has the same state.
TEST(VictimFusionAdopt, AdoptingALaggingPictureKeepsStatesAndDropsOwnVictims) {
  VictimFusion standby;
  FusedVictim located;
  located.victim_id = 1;
  located.position.position = Vec3(0, 0, -1);
  located.position.covariance = 0.25 * Mat3::Identity();
  located.state = VictimState::kLocated;
  located.first_seen = kSec;
  located.located_at = kSec;
  located.sources = {{"a", 1, kSec}};
  standby.update(src("a", 1, kSec, Vec3(0, 0, -1), 0.5, EstimatorStatus::kLocated));
  standby.adopt({located});
  standby.update(src("a", 1, 2 * kSec, Vec3(0, 0, -1), 0.3, EstimatorStatus::kFound));
  standby.update(src("z", 1, 2 * kSec, Vec3(50, 0, -1), 0.5));
  standby.step(2 * kSec);
  ASSERT_EQ(standby.victims().size(), 2U);

  standby.adopt({located});  // the active one's picture of the cycle before
  ASSERT_EQ(standby.victims().size(), 1U) << "a victim the standby opened itself was never published";
  EXPECT_EQ(standby.victims()[0].state, VictimState::kFound);
  EXPECT_EQ(standby.victims()[0].found_at, 2 * kSec);
  EXPECT_EQ(standby.next_id(), 2U);

  FusedVictim found = located;
  found.state = VictimState::kFound;
  found.found_at = 2 * kSec + kSec / 4;
  standby.adopt({found});
  EXPECT_EQ(standby.victims()[0].found_at, 2 * kSec + kSec / 4);
}

// A source the picture lists twice (it cannot: one victim per source) binds to the first.
TEST(VictimFusionAdopt, ASourceListedTwiceBindsOnce) {
  VictimFusion f;
  f.update(src("a", 1, kSec, Vec3(0, 0, -1), 0.5));
  FusedVictim one;
  one.victim_id = 1;
  one.position.covariance = Mat3::Identity();
  one.sources = {{"a", 1, kSec}};
  FusedVictim two = one;
  two.victim_id = 2;
  f.adopt({two, one});
  ASSERT_EQ(f.victims().size(), 2U);
  EXPECT_EQ(f.victims()[0].sources.size(), 1U);
  EXPECT_TRUE(f.victims()[1].sources.empty());
}

}  // namespace
}  // namespace sarloc::incident
