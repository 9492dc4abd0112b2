// VictimFusion over a victim's life: merges, monotonic states, sources timing out, found victims
// that stay where they were found and never merge.
#include <gtest/gtest.h>

#include "sarloc/core/incident/victim_fusion.hpp"
#include "source_estimates.hpp"

namespace sarloc::incident {
namespace {

using responder::EstimatorStatus;
using test::kSec;
using test::src;

TEST(VictimFusion, MergeKeepsLowerIdAndReportsTheOther) {
  VictimFusion f;
  f.update(src("a", 1, 0, Vec3(0, 0, 0), 0.5));
  f.update(src("b", 1, 0, Vec3(20, 0, 0), 0.5));  // far: its own victim
  f.step(0);
  ASSERT_EQ(f.victims().size(), 2u);
  // b's filter moves onto a's victim: its victim's fused estimate now falls inside the gate.
  f.update(src("b", 1, kSec, Vec3(0.5, 0, 0), 0.5));
  f.update(src("a", 1, kSec, Vec3(0, 0, 0), 0.5));
  f.step(kSec);
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_EQ(f.victims()[0].victim_id, 1u);
  EXPECT_EQ(f.victims()[0].sources.size(), 2u);
  EXPECT_EQ(f.take_removed(), (std::vector<std::uint32_t>{2}));
  EXPECT_TRUE(f.take_removed().empty());
}

TEST(VictimFusion, StatesAreMonotonicAndTimesSetOnce) {
  VictimFusion f;
  f.update(src("a", 1, 0, Vec3::Zero()));
  f.step(0);
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kUnconfirmed);
  EXPECT_EQ(f.victims()[0].first_seen, 0);
  f.update(src("a", 1, 1 * kSec, Vec3::Zero(), 1.5, EstimatorStatus::kLocated));
  f.step(1 * kSec);
  EXPECT_EQ(f.victims()[0].state, VictimState::kLocated);
  EXPECT_EQ(f.victims()[0].located_at, 1 * kSec);
  f.update(src("a", 1, 2 * kSec, Vec3::Zero(), 1.5, EstimatorStatus::kConverged));
  f.step(2 * kSec);
  EXPECT_EQ(f.victims()[0].state, VictimState::kLocated);  // never back
  f.update(src("a", 1, 3 * kSec, Vec3::Zero(), 1.5, EstimatorStatus::kFound));
  f.step(3 * kSec);
  EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
  EXPECT_EQ(f.victims()[0].found_at, 3 * kSec);
  EXPECT_EQ(f.victims()[0].located_at, 1 * kSec);
  f.update(src("a", 1, 4 * kSec, Vec3::Zero(), 1.5, EstimatorStatus::kMultimodal));
  f.step(4 * kSec);
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
  EXPECT_TRUE(f.victims()[0].sources.empty());  // multimodal: out of the fusion
  EXPECT_EQ(f.victims()[0].found_at, 3 * kSec);
  EXPECT_EQ(f.victims()[0].last_update, 3 * kSec);
}

// The fused radius confirms what two rescuers' devices agree on; one device's estimate confirms
// only with that device's own state, however small its radius.
TEST(VictimFusion, LocatedByFusedRadiusOfTwoRescuers) {
  VictimFusion f;  // located_radius_m = 1: 95 % radius sqrt(7.81) * sigma < 1 -> sigma < 0.357
  f.update(src("a", 1, 0, Vec3::Zero(), 0.3));
  f.step(0);
  EXPECT_EQ(f.victims()[0].state, VictimState::kUnconfirmed) << "one device, converged";
  f.update(src("c", 1, kSec, Vec3(0.1, 0.0, 0.0), 0.3));
  f.update(src("a", 1, kSec, Vec3::Zero(), 0.3));
  f.step(kSec);
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kLocated);
  f.update(src("b", 1, kSec, Vec3(20, 0, 0), 0.4));
  f.update(src("d", 1, kSec, Vec3(20, 0, 0), 0.4));
  f.step(kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kUnconfirmed) << "fused radius 1.1 m";
}

TEST(VictimFusion, TimedOutSourcesLeaveButTheVictimStays) {
  VictimFusionConfig c;
  c.source_timeout_s = 5.0;
  VictimFusion f(c);
  f.update(src("a", 1, 0, Vec3(1, 2, 0), 1.5, EstimatorStatus::kLocated));
  f.step(0);
  f.step(6 * kSec);
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_TRUE(f.victims()[0].sources.empty());
  EXPECT_TRUE(f.victims()[0].position.position.isApprox(Vec3(1, 2, 0)));
  EXPECT_EQ(f.victims()[0].state, VictimState::kLocated);
  // Another rescuer reaches the same victim later: same id, no duplicate.
  f.update(src("b", 4, 7 * kSec, Vec3(1.5, 2, 0)));
  f.step(7 * kSec);
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_EQ(f.victims()[0].victim_id, 1u);
  EXPECT_EQ(f.victims()[0].sources.size(), 1u);
  EXPECT_EQ(f.remove_source("b"), 1u);
  EXPECT_TRUE(f.victims()[0].sources.empty());
}

// Two victims FOUND 1.5 m apart, each by a rescuer holding a signal in both (so kept apart),
// inside each other's merge gate. Once the rescuers walk off and every source times out, nothing
// new says they are one: both stay, where they were found (seen live: merged into one confirmed
// victim far from both, four within 5 m).
TEST(VictimFusion, TwoConfirmedVictimsThatLostEverySourceStayApart) {
  VictimFusionConfig c;
  c.source_timeout_s = 5.0;
  VictimFusion f(c);
  const Vec3 a(0, 0, -1.2), d(1.0, 0.5, -2.2);
  for (int k = 0; k < 3; ++k) {
    const TimestampNs t = k * kSec;
    f.update(src("r1", 1, t, a, 0.35, EstimatorStatus::kFound));
    f.update(src("r1", 2, t, d, 0.35, EstimatorStatus::kFound));
    f.update(src("r2", 1, t, a, 0.35, EstimatorStatus::kFound));
    f.update(src("r2", 2, t, d, 0.35, EstimatorStatus::kFound));
    f.step(t);
  }
  ASSERT_EQ(f.victims().size(), 2u);
  for (const auto& v : f.victims()) EXPECT_EQ(v.state, VictimState::kFound);
  f.step(20 * kSec);  // every source timed out
  ASSERT_EQ(f.victims().size(), 2u) << "two found victims merged without new evidence";
  for (const auto& v : f.victims()) {
    EXPECT_TRUE(v.sources.empty());
    EXPECT_LT(std::min((v.position.position - a).norm(), (v.position.position - d).norm()), 0.2);
  }
  // An unconfirmed source arriving near one of them still joins it: no duplicate.
  f.update(src("r3", 7, 21 * kSec, a + Vec3(0.1, 0, 0), 0.3));
  f.step(21 * kSec);
  EXPECT_EQ(f.victims().size(), 2u);
}

// r1's device stands over a victim; r2's source of it (a mixed signal, say) sits 0.9 m deeper
// with a wider radius, inside the keep gate. The dig site is r1's, and it stays there once r1
// walks on while r2's source drifts further. Before, every update re-fused it from all bound
// sources (live, four within 5 m under load: a FOUND victim moved 2.4 m, 2.1 m too deep).
TEST(VictimFusion, AFoundVictimStaysWhereItsFinderFoundIt) {
  VictimFusionConfig c;
  c.source_timeout_s = 5.0;
  VictimFusion f(c);
  const Vec3 a(2.0, 40.0, -1.0);
  for (int k = 0; k < 3; ++k) {
    const TimestampNs t = k * kSec;
    f.update(src("r1", 1, t, a, 0.15, k == 0 ? EstimatorStatus::kConverged : EstimatorStatus::kFound));
    f.update(src("r2", 4, t, a + Vec3(0.2, 0.0, -0.9), 0.5));
    f.step(t);
  }
  ASSERT_EQ(f.victims().size(), 1u);
  const FusedVictim& v = f.victims()[0];
  ASSERT_EQ(v.state, VictimState::kFound);
  ASSERT_EQ(v.sources.size(), 2u) << "r2's source is bound: it could move the victim";
  EXPECT_LT((v.position.position - a).norm(), 1e-9);
  EXPECT_NEAR(v.position.covariance(2, 2), 0.15 * 0.15, 1e-12) << "the finder's own radius";
  // r1 walks on; r2's source drifts another 1.5 m down.
  for (int k = 4; k < 12; ++k) {
    const TimestampNs t = k * kSec;
    f.update(src("r2", 4, t, a + Vec3(0.2, 0.0, -0.9 - 0.2 * (k - 4)), 0.5));
    f.step(t);
  }
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
  EXPECT_EQ(f.victims()[0].sources.size(), 1u);
  EXPECT_LT((f.victims()[0].position.position - a).norm(), 1e-9) << "the dig site moved";
  // r1 comes back and finds it again 0.3 m over: the dig site follows its finder.
  f.update(src("r1", 1, 13 * kSec, a + Vec3(0.3, 0.0, 0.0), 0.15, EstimatorStatus::kFound));
  f.step(13 * kSec);
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_LT((f.victims()[0].position.position - (a + Vec3(0.3, 0.0, 0.0))).norm(), 1e-9);
}

// Two victims 1.2 m apart, each found by a different rescuer's device: two dig sites, inside
// each other's merge gate with no rescuer holding a signal in both. They never merge: before, the
// second left the picture and the first moved to a point between them (live, four within 5 m).
TEST(VictimFusion, TwoFoundVictimsNeverMerge) {
  VictimFusion f;
  const Vec3 a(0.0, 0.0, -1.2), d_far(3.0, 0.0, -1.2), d(1.2, 0.0, -1.2);
  for (int k = 0; k < 3; ++k) {
    const TimestampNs t = k * kSec;
    f.update(src("r1", 1, t, a, 0.35, EstimatorStatus::kFound));
    f.update(src("r2", 1, t, d_far, 0.35, EstimatorStatus::kFound));
    f.step(t);
  }
  ASSERT_EQ(f.victims().size(), 2u);
  // r2's estimate comes to 1.2 m from a: d^2 = 1.44 / (2 * 0.35^2) = 5.9, inside the merge gate.
  for (int k = 3; k < 6; ++k) {
    const TimestampNs t = k * kSec;
    f.update(src("r1", 1, t, a, 0.35, EstimatorStatus::kFound));
    f.update(src("r2", 1, t, d, 0.35, EstimatorStatus::kFound));
    f.step(t);
  }
  ASSERT_EQ(f.victims().size(), 2u) << "two found victims merged";
  EXPECT_TRUE(f.take_removed().empty());
  EXPECT_LT((f.victims()[0].position.position - a).norm(), 1e-9);
  EXPECT_LT((f.victims()[1].position.position - d).norm(), 1e-9);
  // An unconfirmed victim there still merges into a found one, which keeps its dig site.
  f.update(src("r3", 2, 6 * kSec, a + Vec3(-4.0, 0.0, 0.0), 0.35));
  f.step(6 * kSec);
  ASSERT_EQ(f.victims().size(), 3u);
  f.update(src("r3", 2, 7 * kSec, a + Vec3(-0.5, 0.0, 0.0), 0.35));
  f.update(src("r1", 1, 7 * kSec, a, 0.35, EstimatorStatus::kFound));
  f.update(src("r2", 1, 7 * kSec, d, 0.35, EstimatorStatus::kFound));
  f.step(7 * kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[0].sources.size(), 2u);
  EXPECT_LT((f.victims()[0].position.position - a).norm(), 1e-9);
}

}  // namespace
}  // namespace sarloc::incident
