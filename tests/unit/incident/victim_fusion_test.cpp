// VictimFusion: its config, bad input, sources and their estimators (device and daemon),
// conflicts, and which sources make one victim.
#include "sarloc/core/incident/victim_fusion.hpp"

#include <gtest/gtest.h>

#include <set>

#include "sarloc/core/common/errors.hpp"
#include "source_estimates.hpp"
#include "support/config_messages.hpp"

namespace sarloc::incident {
namespace {

using responder::EstimatorStatus;
using test::kSec;
using test::src;

TEST(VictimFusion, ConfigDefaultsValidAndMessages) {
  EXPECT_NO_THROW(VictimFusionConfig{}.validate());
  VictimFusionConfig c;
  c.gate_probability = 1.5;
  EXPECT_EQ(sarloc::test::validation_error(c), "fusion.gate_probability = 1.5: must be in (0, 1)");
  c = {};
  c.keep_gate_probability = 0.9;
  EXPECT_EQ(sarloc::test::validation_error(c), "fusion.keep_gate_probability = 0.9: must be >= gate_probability");
  c = {};
  c.source_timeout_s = 0.0;
  EXPECT_EQ(sarloc::test::validation_error(c), "fusion.source_timeout_s = 0: must be in (0, 3600]");
  c = {};
  c.located_radius_m = -1.0;
  EXPECT_EQ(sarloc::test::validation_error(c), "fusion.located_radius_m = -1: must be in (0, 100]");
  c = {};
  c.merge_gate_probability = 0.0;
  EXPECT_EQ(sarloc::test::validation_error(c), "fusion.merge_gate_probability = 0: must be in (0, 1)");
  EXPECT_THROW(VictimFusion{c}, ConfigError);
}

TEST(VictimFusion, RejectsBadInputAndIgnoresOlderStamps) {
  VictimFusion f;
  EXPECT_THROW(f.update(src("", 1, 0, Vec3::Zero())), InputError);
  SourceEstimate bad = src("a", 1, 0, Vec3::Zero());
  bad.position.covariance(0, 0) = -1.0;
  EXPECT_THROW(f.update(bad), InputError);
  bad = src("a", 1, 0, Vec3(std::nan(""), 0, 0));
  EXPECT_THROW(f.update(bad), InputError);
  EXPECT_TRUE(f.update(src("a", 1, 2 * kSec, Vec3::Zero())));
  EXPECT_FALSE(f.update(src("a", 1, 1 * kSec, Vec3::Ones())));
}

// A buried victim cannot be above the snow surface (z = 0): such an estimate comes from a
// filter on its mirror solution and must not open a victim. Within 5 sigma it is kept.
TEST(VictimFusion, RefusesAnEstimateAboveTheSnowSurface) {
  VictimFusion f;
  try {
    f.update(src("a", 1, kSec, Vec3(1.0, 2.0, 30.6), 0.4));
    FAIL() << "30 m above the surface accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("source_estimate[a/1].position.z = 30.6"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(f.update(src("a", 1, kSec, Vec3(1.0, 2.0, 1.5), 0.4))) << "1.5 m up with sigma 0.4: noise";
  f.step(2 * kSec);
  EXPECT_EQ(f.victims().size(), 1u);
  EXPECT_THROW(f.update(src("b", 1, kSec, Vec3(1.0, 2.0, 2.5), 0.4)), InputError);
}

TEST(VictimFusion, MakeSourceEstimateUsesTheTransform) {
  responder::VictimEstimate e;
  e.rescuer_id = "r1";
  e.signal_id = 7;
  e.stamp = 42;
  e.status = EstimatorStatus::kLocated;
  e.relative.position = Vec3(1, 2, -1);
  e.relative.covariance = 0.04 * Mat3::Identity();
  ReporterFix fix;
  fix.antenna.position = Vec3(10, 20, 1);
  fix.antenna.covariance = 2.25 * Mat3::Identity();
  fix.floor = 2;
  const SourceEstimate s = make_source_estimate(e, fix);
  EXPECT_EQ(s.rescuer_id, "r1");
  EXPECT_EQ(s.signal_id, 7u);
  EXPECT_EQ(s.stamp, 42);
  EXPECT_EQ(s.state, SourceState::kLocated);
  EXPECT_EQ(s.floor, 2);
  EXPECT_FALSE(s.below_surface);
  EXPECT_TRUE(s.position.position.isApprox(Vec3(11, 22, 0)));
  EXPECT_TRUE(s.position.covariance.isApprox(2.29 * Mat3::Identity()));
}

// A GNSS fix places victims with heights above the snow (the antenna's height replaces the
// GNSS altitude); an indoor fix keeps its height and floor: a firefighter on the second floor
// reports a victim up there, not at antenna height above the ground.
TEST(VictimFusion, ReporterFixKeepsIndoorHeightsAndFloorsAndMapsGnssToTheSnowSurface) {
  responder::ResponderPosition p;
  p.position.position = Vec3(5, 6, 2321.0);
  p.position.covariance = 4.0 * Mat3::Identity();
  p.source = responder::PositionSource::kGnss;
  const ReporterFix outdoor = reporter_fix_of(p, 1.2, 0.1);
  EXPECT_DOUBLE_EQ(outdoor.antenna.position.z(), 1.2);
  EXPECT_DOUBLE_EQ(outdoor.antenna.covariance(2, 2), 0.01);
  EXPECT_DOUBLE_EQ(outdoor.antenna.covariance(0, 2), 0.0);
  EXPECT_DOUBLE_EQ(outdoor.antenna.position.x(), 5.0);
  EXPECT_TRUE(outdoor.heights_above_surface);

  p.source = responder::PositionSource::kMapAided;
  p.position.position = Vec3(5, 6, 7.5);
  p.floor = 2;
  const ReporterFix indoor = reporter_fix_of(p, 1.2, 0.1);
  EXPECT_DOUBLE_EQ(indoor.antenna.position.z(), 7.5);
  EXPECT_EQ(indoor.floor, 2);
  EXPECT_FALSE(indoor.heights_above_surface);
}

// A rescuer's device and the core daemon estimate the same (rescuer, signal) from the same
// samples. When they confidently disagree, one is wrong and the picture cannot tell which:
// the source confirms nothing, the victim is flagged, and nothing is confirmed on it alone.
TEST(VictimFusion, EachSourceShowsItsSignalsLastSeparationEvent) {
  VictimFusion f;
  f.update(src("r1", 1, 10 * kSec, Vec3(-20.0, 42.0, -1.2), 0.3));
  f.step(10 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  EXPECT_EQ(f.victims()[0].sources.at(0).signal_event, responder::SignalEvent::kNone);
  SourceEstimate separated = src("r1", 1, 11 * kSec, Vec3(-20.1, 42.0, -1.2), 0.3);
  separated.signal_event = responder::SignalEvent::kSeparated;
  separated.signal_event_stamp = 11 * kSec;
  f.update(separated);
  f.step(11 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  EXPECT_EQ(f.victims()[0].sources.at(0).signal_event, responder::SignalEvent::kSeparated);
  EXPECT_EQ(f.victims()[0].sources.at(0).signal_event_stamp, 11 * kSec);
}

TEST(VictimFusion, ConflictingEstimatorsOfOneSourceConfirmNothing) {
  VictimFusion f;
  SourceEstimate device = src("r1", 1, 10 * kSec, Vec3(-20.0, 42.0, -1.2), 0.15, EstimatorStatus::kLocated);
  device.estimator = "device";
  SourceEstimate daemon = src("r1", 1, 11 * kSec, Vec3(-27.9, 40.8, -1.8), 0.15, EstimatorStatus::kLocated);
  daemon.estimator = "daemon";
  f.update(device);
  f.update(daemon);
  f.step(11 * kSec);
  for (const auto& v : f.victims()) {
    EXPECT_EQ(v.state, VictimState::kUnconfirmed) << "victim " << v.victim_id;
  }
  // Another rescuer agrees with the device: that victim is confirmed on its evidence.
  f.update(src("r2", 1, 12 * kSec, Vec3(-20.1, 42.1, -1.2), 0.15, EstimatorStatus::kLocated));
  f.step(12 * kSec);
  ASSERT_EQ(f.victims().size(), 1U) << "the conflicted source opened no victim of its own";
  EXPECT_EQ(f.victims()[0].state, VictimState::kLocated);
  EXPECT_TRUE(f.victims()[0].position.position.isApprox(Vec3(-20.1, 42.1, -1.2), 1e-9));
}

TEST(VictimFusion, AConfirmedVictimWhoseOnlySourceTurnsConflictedIsNoLongerConfirmed) {
  VictimFusion f;
  SourceEstimate daemon = src("r1", 1, 10 * kSec, Vec3(-27.9, 40.8, -1.8), 0.15, EstimatorStatus::kLocated);
  daemon.estimator = "daemon";
  f.update(daemon);
  f.step(10 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  ASSERT_EQ(f.victims()[0].state, VictimState::kLocated);
  SourceEstimate device = src("r1", 1, 11 * kSec, Vec3(-20.0, 42.0, -1.2), 0.15, EstimatorStatus::kLocated);
  device.estimator = "device";
  f.update(device);
  f.step(11 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  EXPECT_TRUE(f.victims()[0].evidence_conflict);
  EXPECT_EQ(f.victims()[0].state, VictimState::kUnconfirmed);
  EXPECT_EQ(f.victims()[0].located_at, 0);
}

// The reporter's own device saw every sample; the daemon's copy may have missed some in a
// fade. In their conflict the source follows the device, and the victim stays flagged.
TEST(VictimFusion, InAConflictWithTheDaemonTheDevicesEstimateCarriesTheSource) {
  VictimFusion f;
  SourceEstimate daemon = src("r1", 1, 10 * kSec, Vec3(-27.9, 40.8, -1.8), 0.15, EstimatorStatus::kLocated);
  daemon.estimator = "daemon";
  daemon.from_device = false;
  SourceEstimate device = src("r1", 1, 10 * kSec, Vec3(-20.0, 42.0, -1.2), 0.15, EstimatorStatus::kFound);
  device.estimator = "device";
  f.update(daemon);
  f.update(device);
  SourceEstimate later = daemon;  // the daemon keeps publishing its wrong copy
  later.stamp = 11 * kSec;
  EXPECT_FALSE(f.update(later)) << "not the estimator the conflicted source follows";
  f.step(11 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  const auto& v = f.victims()[0];
  EXPECT_TRUE(v.position.position.isApprox(Vec3(-20.0, 42.0, -1.2), 1e-9));
  EXPECT_EQ(v.state, VictimState::kFound);
  EXPECT_TRUE(v.evidence_conflict);
}

// The daemon's copy can miss samples in a fade: alone it shows where a victim may be, but a
// LOCATED or FOUND daemon estimate (or a tight fused radius) confirms nothing until the
// reporter's own device, which saw every sample, says so too.
TEST(VictimFusion, OnlyTheReportersOwnDeviceConfirms) {
  VictimFusion f;
  SourceEstimate daemon = src("r1", 1, 10 * kSec, Vec3(-20.0, 42.0, -1.2), 0.1, EstimatorStatus::kFound);
  daemon.estimator = "daemon";
  daemon.from_device = false;
  f.update(daemon);
  f.step(10 * kSec);
  ASSERT_EQ(f.victims().size(), 1U) << "the daemon's estimate still places a victim";
  EXPECT_EQ(f.victims()[0].state, VictimState::kUnconfirmed) << "FOUND and a 0.2 m radius from the daemon alone";
  SourceEstimate device = src("r1", 1, 11 * kSec, Vec3(-20.05, 42.0, -1.2), 0.1, EstimatorStatus::kConverged);
  device.estimator = "device";
  f.update(device);
  f.step(11 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  EXPECT_EQ(f.victims()[0].state, VictimState::kUnconfirmed)
      << "corroborated, but one device's CONVERGED: the radius rule needs two rescuers";
  SourceEstimate found = device;
  found.stamp = 12 * kSec;
  found.state = SourceState::kFound;
  f.update(found);
  f.step(12 * kSec);
  EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
}

// Seen under radio fades: the daemon restarted its filter next to a victim the device had
// FOUND; its fresh filter claimed CONVERGED 10 m off with newer stamps, and the device's
// FOUND (republished with the stamp of its epoch) arrived 16 s late.
TEST(VictimFusion, TheDevicesFoundHoldsItsSourceAgainstNewerDaemonEstimates) {
  VictimFusion f;
  SourceEstimate daemon = src("r1", 1, 26 * kSec, Vec3(-17.0, 40.0, -1.5), 0.5, EstimatorStatus::kConverged);
  daemon.estimator = "daemon";
  daemon.from_device = false;
  EXPECT_TRUE(f.update(daemon));
  SourceEstimate found = src("r1", 1, 10 * kSec, Vec3(-6.0, 35.0, -1.0), 0.1, EstimatorStatus::kFound);
  found.estimator = "device";
  found.received = 27 * kSec;
  EXPECT_TRUE(f.update(found)) << "older stamp, but the device's FOUND";
  f.step(27 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  EXPECT_EQ(f.victims()[0].state, VictimState::kFound) << "heard 17 s after its stamp, still active";
  EXPECT_TRUE(f.victims()[0].position.position.isApprox(Vec3(-6.0, 35.0, -1.0), 1e-9));
  daemon.stamp = 28 * kSec;
  EXPECT_FALSE(f.update(daemon)) << "the daemon's copy does not replace the device's FOUND";
  f.step(28 * kSec);
  EXPECT_TRUE(f.victims()[0].position.position.isApprox(Vec3(-6.0, 35.0, -1.0), 1e-9));
}

TEST(VictimFusion, ADeviceEstimateOlderThanTheTimeoutCorroboratesNothing) {
  VictimFusionConfig c;
  c.source_timeout_s = 5.0;
  VictimFusion f(c);
  SourceEstimate device = src("r1", 1, 1 * kSec, Vec3(-20.0, 42.0, -1.2), 1.5, EstimatorStatus::kConverged);
  device.estimator = "device";
  f.update(device);
  SourceEstimate daemon = src("r1", 1, 9 * kSec, Vec3(-20.0, 42.0, -1.2), 0.1, EstimatorStatus::kLocated);
  daemon.estimator = "daemon";
  daemon.from_device = false;
  f.update(daemon);
  f.step(9 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  EXPECT_EQ(f.victims()[0].state, VictimState::kUnconfirmed);
}

TEST(VictimFusion, WithoutTheDeviceRuleAnyEstimatorConfirms) {
  VictimFusionConfig c;
  c.confirm_requires_device = false;
  VictimFusion f(c);
  SourceEstimate daemon = src("r1", 1, 10 * kSec, Vec3(-20.0, 42.0, -1.2), 0.1, EstimatorStatus::kLocated);
  daemon.from_device = false;
  f.update(daemon);
  f.step(10 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  EXPECT_EQ(f.victims()[0].state, VictimState::kLocated);
}

TEST(VictimFusion, AgreeingEstimatorsAreNoConflict) {
  VictimFusion f;
  SourceEstimate device = src("r1", 1, 10 * kSec, Vec3(-20.0, 42.0, -1.2), 0.15, EstimatorStatus::kLocated);
  device.estimator = "device";
  SourceEstimate daemon = src("r1", 1, 11 * kSec, Vec3(-20.1, 42.05, -1.25), 0.15, EstimatorStatus::kLocated);
  daemon.estimator = "daemon";
  f.update(device);
  f.update(daemon);
  f.step(11 * kSec);
  ASSERT_EQ(f.victims().size(), 1U);
  EXPECT_FALSE(f.victims()[0].evidence_conflict);
  EXPECT_EQ(f.victims()[0].state, VictimState::kLocated);
}

TEST(VictimFusion, AnIndoorVictimAboveGroundIsAcceptedAndFloorsNeverMix) {
  VictimFusion f;
  SourceEstimate upstairs = src("ff1", 1, kSec, Vec3(3, 3, 6.0), 0.3);
  upstairs.below_surface = false;
  upstairs.floor = 2;
  EXPECT_TRUE(f.update(upstairs)) << "no snow surface indoors";
  SourceEstimate below = src("ff2", 1, kSec, Vec3(3, 3, 5.5), 0.3);  // same x, y, a floor lower
  below.below_surface = false;
  below.floor = 1;
  f.update(below);
  f.step(kSec);
  ASSERT_EQ(f.victims().size(), 2U) << "sources on different floors must not associate or merge";
  EXPECT_NE(f.victims()[0].floor, f.victims()[1].floor);
}

TEST(VictimFusion, OnlyConvergedSourcesTakePart) {
  VictimFusion f;
  f.update(src("a", 1, 0, Vec3::Zero(), 1.5, EstimatorStatus::kMultimodal));
  f.step(0);
  EXPECT_TRUE(f.victims().empty());
  f.update(src("a", 1, kSec, Vec3::Zero()));
  f.step(kSec);
  EXPECT_EQ(f.victims().size(), 1u);
}

TEST(VictimFusion, TwoRescuersOneVictim) {
  VictimFusion f;
  f.update(src("a", 3, 0, Vec3(10.0, 5.0, -1.0)));
  f.update(src("b", 9, 0, Vec3(11.5, 4.0, -1.5)));
  f.step(0);
  ASSERT_EQ(f.victims().size(), 1u);
  const FusedVictim& v = f.victims()[0];
  EXPECT_EQ(v.victim_id, 1u);
  EXPECT_EQ(v.sources.size(), 2u);
  EXPECT_TRUE(v.position.position.isApprox(Vec3(10.75, 4.5, -1.25), 1e-9));  // equal P: average
  EXPECT_TRUE(v.position.covariance.isApprox(2.25 * Mat3::Identity(), 1e-9));  // CI: no shrink
  EXPECT_EQ(v.state, VictimState::kUnconfirmed);
}

TEST(VictimFusion, SameRescuerSignalsNeverShareAVictim) {
  VictimFusion f;
  for (int k = 0; k < 20; ++k) {
    const TimestampNs t = k * kSec;
    f.update(src("a", 1, t, Vec3(0.0, 0.0, -1.0)));
    f.update(src("a", 2, t, Vec3(0.3, 0.0, -1.0)));  // well inside each other's gate
    if (k >= 5) f.update(src("b", 1, t, Vec3(0.15, 0.1, -1.0)));  // between them
    f.step(t);
    ASSERT_EQ(f.victims().size(), 2u) << "step " << k;
    for (const FusedVictim& v : f.victims()) {
      std::set<std::string> rescuers;
      for (const VictimSource& s : v.sources) EXPECT_TRUE(rescuers.insert(s.rescuer_id).second);
    }
    EXPECT_EQ(f.victims()[0].victim_id, 1u);
    EXPECT_EQ(f.victims()[1].victim_id, 2u);
  }
  EXPECT_TRUE(f.take_removed().empty());
}

}  // namespace
}  // namespace sarloc::incident
