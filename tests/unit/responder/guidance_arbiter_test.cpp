// GuidanceArbiter: whose guidance a device follows, and when the daemon counts as reachable.
#include "sarloc/core/responder/guidance_arbiter.hpp"

#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::responder {
namespace {

constexpr TimestampNs kS = 1'000'000'000;

Guidance guidance(std::uint32_t signal, double heading) {
  Guidance g;
  g.rescuer_id = "r1";
  g.signal_id = signal;
  g.heading_rad = heading;
  return g;
}

ArbiterInput input(TimestampNs now_s, std::uint64_t sequence, std::optional<Guidance> local,
                   EstimatorStatus local_status = EstimatorStatus::kMultimodal) {
  ArbiterInput in;
  in.now = now_s * kS;
  in.sequence = sequence;
  in.published_wall_ns = 1000;
  in.local_guidance = std::move(local);
  in.local_status = [local_status](std::uint32_t) { return local_status; };
  return in;
}

TEST(GuidanceArbiter, FollowsTheDaemonsAnswerToThisEpochWhenItIsAsFarAlong) {
  GuidanceArbiter a(3.0, 0);
  EXPECT_FALSE(a.answered(5));
  a.on_daemon_guidance(guidance(1, 0.5), 5, 1 * kS, 3'001'000);
  EXPECT_FALSE(a.answered(5)) << "the guided signal's estimate for this epoch is still missing";
  a.on_daemon_estimate(1, EstimatorStatus::kConverged, 5, 1 * kS);
  EXPECT_TRUE(a.answered(5));
  const auto d = a.decide(input(1, 5, guidance(1, -1.0)));
  EXPECT_EQ(d.source, GuidanceSource::kDaemon);
  ASSERT_TRUE(d.guidance.has_value());
  EXPECT_DOUBLE_EQ(d.guidance->heading_rad, 0.5);
  EXPECT_TRUE(d.daemon_reachable);
  EXPECT_NEAR(d.latency_ms, 3.0, 1e-9);
  EXPECT_EQ(d.daemon_signals.at(1), EstimatorStatus::kConverged);
}

TEST(GuidanceArbiter, ALessAdvancedDaemonIsNotFollowed) {
  // A restarted daemon starts from nothing: its fresh mixture must not override the device's
  // converged search.
  GuidanceArbiter a(3.0, 0);
  a.on_daemon_guidance(guidance(1, 0.5), 5, 1 * kS, 0);
  a.on_daemon_estimate(1, EstimatorStatus::kMultimodal, 5, 1 * kS);
  const auto d = a.decide(input(1, 5, guidance(1, -1.0), EstimatorStatus::kLocated));
  EXPECT_EQ(d.source, GuidanceSource::kLocal);
  EXPECT_DOUBLE_EQ(d.guidance->heading_rad, -1.0);
  EXPECT_TRUE(d.daemon_reachable);
}

TEST(GuidanceArbiter, AnAnswerToAnotherEpochIsNotFollowed) {
  GuidanceArbiter a(3.0, 0);
  a.on_daemon_guidance(guidance(1, 0.5), 4, 1 * kS, 0);
  a.on_daemon_estimate(1, EstimatorStatus::kLocated, 4, 1 * kS);
  const auto d = a.decide(input(1, 5, guidance(1, -1.0)));
  EXPECT_EQ(d.source, GuidanceSource::kLocal);
  EXPECT_LT(d.latency_ms, 0.0);
}

TEST(GuidanceArbiter, ALateAnswerToAnOlderEpochNeverReplacesANewerOne) {
  GuidanceArbiter a(3.0, 0);
  a.on_daemon_guidance(guidance(1, 0.5), 6, 1 * kS, 0);
  a.on_daemon_guidance(guidance(1, 2.0), 5, 1 * kS, 0);  // retransmitted late
  a.on_daemon_estimate(1, EstimatorStatus::kConverged, 6, 1 * kS);
  const auto d = a.decide(input(1, 6, std::nullopt));
  ASSERT_EQ(d.source, GuidanceSource::kDaemon);
  EXPECT_DOUBLE_EQ(d.guidance->heading_rad, 0.5);
}

TEST(GuidanceArbiter, SilenceBeyondTheTimeoutFallsBackOnceAndAnAnswerReconnects) {
  GuidanceArbiter a(3.0, 0);
  EXPECT_TRUE(a.decide(input(1, 1, guidance(1, 0.0))).daemon_reachable) << "grace period before any answer";
  EXPECT_TRUE(a.worth_waiting());
  auto d = a.decide(input(4, 4, guidance(1, 0.0)));
  EXPECT_FALSE(d.daemon_reachable);
  EXPECT_TRUE(d.fell_back);
  EXPECT_EQ(a.fallbacks(), 1);
  d = a.decide(input(5, 5, guidance(1, 0.0)));
  EXPECT_FALSE(d.fell_back) << "one fallback, not one per epoch";
  EXPECT_EQ(a.fallbacks(), 1);
  EXPECT_TRUE(a.worth_waiting()) << "never answered yet: worth a wait in case it shows up";
  a.on_daemon_estimate(1, EstimatorStatus::kMultimodal, 6, 6 * kS);
  d = a.decide(input(6, 6, guidance(1, 0.0)));
  EXPECT_TRUE(d.daemon_reachable);
  EXPECT_TRUE(d.reconnected);
  EXPECT_TRUE(a.worth_waiting());
}

TEST(GuidanceArbiter, LostLivelinessMakesTheDaemonUnreachableAtOnceAndForgetsItsStatuses) {
  GuidanceArbiter a(3.0, 0);
  a.on_daemon_seen();
  a.on_daemon_guidance(guidance(1, 0.5), 5, 1 * kS, 0);
  a.on_daemon_estimate(1, EstimatorStatus::kConverged, 5, 1 * kS);
  a.on_daemons_lost();
  auto d = a.decide(input(1, 5, guidance(1, -1.0)));
  EXPECT_FALSE(d.daemon_reachable);
  EXPECT_TRUE(d.daemons_lost);
  EXPECT_EQ(d.source, GuidanceSource::kLocal);
  EXPECT_FALSE(a.answered(5)) << "statuses of the lost daemon are forgotten";
  a.on_daemon_seen();  // a daemon (re)appeared
  d = a.decide(input(2, 6, guidance(1, -1.0)));
  EXPECT_TRUE(d.daemon_reachable);
}

TEST(GuidanceArbiter, NothingToFollowWithoutAnyGuidance) {
  GuidanceArbiter a(3.0, 0);
  const auto d = a.decide(input(1, 0, std::nullopt));
  EXPECT_EQ(d.source, GuidanceSource::kNone);
  EXPECT_FALSE(d.guidance.has_value());
}

VictimEstimate estimate(std::uint32_t signal, EstimatorStatus status, const Vec3& p, double sigma) {
  VictimEstimate e;
  e.rescuer_id = "r1";
  e.signal_id = signal;
  e.status = status;
  e.relative.position = p;
  e.relative.covariance = sigma * sigma * Mat3::Identity();
  return e;
}

// The daemon and the device filter the same samples: a confident disagreement means one of
// them is wrong. The device keeps its own guidance and reports the conflict.
TEST(GuidanceArbiter, AConflictingDaemonEstimateIsNotFollowedAndIsReported) {
  GuidanceArbiter a(3.0, 0);
  GaussianPosition daemon;
  daemon.position = Vec3(-3.2, 1.5, -2.5);  // the daemon's LOCATED estimate after a long fade
  daemon.covariance = 0.04 * Mat3::Identity();
  a.on_daemon_guidance(guidance(1, 2.7), 9, 1 * kS, 0);
  a.on_daemon_estimate(1, EstimatorStatus::kLocated, 9, 1 * kS, daemon);
  auto in = input(1, 9, guidance(1, 0.6), EstimatorStatus::kConverged);
  in.local_estimates = {estimate(1, EstimatorStatus::kConverged, Vec3(4.3, 3.4, -2.2), 0.3)};
  const auto d = a.decide(in);
  EXPECT_EQ(d.source, GuidanceSource::kLocal) << "a LOCATED daemon outranks the device, but it contradicts it";
  EXPECT_DOUBLE_EQ(d.guidance->heading_rad, 0.6);
  EXPECT_EQ(d.conflicting_signals, std::set<std::uint32_t>{1});
}

TEST(GuidanceArbiter, AgreeingOrUnsettledEstimatesAreNoConflict) {
  GuidanceArbiter a(3.0, 0);
  GaussianPosition daemon;
  daemon.position = Vec3(4.1, 3.3, -2.2);
  daemon.covariance = 0.04 * Mat3::Identity();
  a.on_daemon_guidance(guidance(1, 0.5), 9, 1 * kS, 0);
  a.on_daemon_estimate(1, EstimatorStatus::kLocated, 9, 1 * kS, daemon);
  const auto agreeing = estimate(1, EstimatorStatus::kConverged, Vec3(4.3, 3.4, -2.2), 0.3);
  EXPECT_FALSE(a.conflicts(agreeing, 9));
  const auto multimodal = estimate(1, EstimatorStatus::kMultimodal, Vec3(-20, 3.4, -2.2), 0.3);
  EXPECT_FALSE(a.conflicts(multimodal, 9)) << "a multimodal mean says nothing";
  const auto far = estimate(1, EstimatorStatus::kConverged, Vec3(-20, 3.4, -2.2), 0.3);
  EXPECT_TRUE(a.conflicts(far, 9));
  EXPECT_FALSE(a.conflicts(far, 10)) << "estimates of different epochs are in different frames";
  auto in = input(1, 9, guidance(1, 0.6), EstimatorStatus::kConverged);
  in.local_estimates = {agreeing};
  const auto d = a.decide(in);
  EXPECT_EQ(d.source, GuidanceSource::kDaemon);
  EXPECT_TRUE(d.conflicting_signals.empty());
}

// One daemon answer lost under packet loss sends the device to its own guidance; it comes
// back to the daemon only after rejoin_epochs answers in a row, not at the next one.
TEST(GuidanceArbiter, BackToTheDaemonOnlyAfterRejoinEpochsAnswersInARow) {
  GuidanceArbiter a(3.0, 0, 3);
  auto answer = [&](std::uint64_t seq) {
    a.on_daemon_guidance(guidance(1, 0.5), seq, static_cast<TimestampNs>(seq) * kS, 0);
    a.on_daemon_estimate(1, EstimatorStatus::kConverged, seq, static_cast<TimestampNs>(seq) * kS);
  };
  auto decide = [&](std::uint64_t seq) {
    return a.decide(input(static_cast<TimestampNs>(seq), seq, guidance(1, -1.0), EstimatorStatus::kConverged)).source;
  };
  answer(1);
  EXPECT_EQ(decide(1), GuidanceSource::kDaemon) << "the first answer is followed at once";
  EXPECT_EQ(decide(2), GuidanceSource::kLocal) << "epoch 2's answer was lost";
  std::vector<GuidanceSource> after;
  for (std::uint64_t seq = 3; seq <= 6; ++seq) {
    answer(seq);
    after.push_back(decide(seq));
  }
  EXPECT_EQ(after, (std::vector<GuidanceSource>{GuidanceSource::kLocal, GuidanceSource::kLocal,
                                                GuidanceSource::kDaemon, GuidanceSource::kDaemon}));
  EXPECT_EQ(a.switches(), 2) << "daemon -> device -> daemon";
  EXPECT_EQ(decide(7), GuidanceSource::kLocal);
  EXPECT_EQ(a.switches(), 3);
}

TEST(GuidanceArbiter, WithoutOwnGuidanceTheDaemonIsFollowedAtOnce) {
  GuidanceArbiter a(3.0, 0, 5);
  a.on_daemon_guidance(guidance(1, 0.5), 1, 1 * kS, 0);
  a.on_daemon_estimate(1, EstimatorStatus::kConverged, 1, 1 * kS);
  EXPECT_EQ(a.decide(input(1, 1, guidance(1, -1.0), EstimatorStatus::kConverged)).source, GuidanceSource::kDaemon);
  EXPECT_EQ(a.decide(input(2, 2, guidance(1, -1.0), EstimatorStatus::kConverged)).source, GuidanceSource::kLocal);
  a.on_daemon_guidance(guidance(1, 0.5), 3, 3 * kS, 0);
  a.on_daemon_estimate(1, EstimatorStatus::kConverged, 3, 3 * kS);
  EXPECT_EQ(a.decide(input(3, 3, std::nullopt)).source, GuidanceSource::kDaemon)
      << "the device has nothing of its own to guide with";
}

TEST(GuidanceArbiter, RefusesAnAbsurdTimeout) {
  EXPECT_THROW(GuidanceArbiter(0.0, 0), ConfigError);
  EXPECT_THROW(GuidanceArbiter(1e6, 0), ConfigError);
  EXPECT_THROW(GuidanceArbiter(3.0, 0, 0), ConfigError);
  EXPECT_THROW(GuidanceArbiter(3.0, 0, 101), ConfigError);
}

}  // namespace
}  // namespace sarloc::responder
