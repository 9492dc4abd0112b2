#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <random>
#include <set>

#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/victim_fusion.hpp"

namespace sarloc::incident {
namespace {

using responder::EstimatorStatus;
constexpr TimestampNs kSec = 1'000'000'000;

SourceEstimate src(const std::string& rescuer, std::uint32_t signal, TimestampNs t, const Vec3& p,
                   double sigma = 1.5, EstimatorStatus st = EstimatorStatus::kConverged) {
  SourceEstimate s;
  s.rescuer_id = rescuer;
  s.signal_id = signal;
  s.stamp = t;
  s.position.position = p;
  s.position.covariance = sigma * sigma * Mat3::Identity();
  s.state = source_state_of(st);
  s.below_surface = true;  // avalanche victims: heights above the snow
  s.from_device = true;     // the reporter's own estimate unless a test says otherwise
  return s;
}

std::string message_of(const VictimFusionConfig& c) {
  try {
    c.validate();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(VictimFusion, ConfigDefaultsValidAndMessages) {
  EXPECT_NO_THROW(VictimFusionConfig{}.validate());
  VictimFusionConfig c;
  c.gate_probability = 1.5;
  EXPECT_EQ(message_of(c), "fusion.gate_probability = 1.5: must be in (0, 1)");
  c = {};
  c.keep_gate_probability = 0.9;
  EXPECT_EQ(message_of(c), "fusion.keep_gate_probability = 0.9: must be >= gate_probability");
  c = {};
  c.source_timeout_s = 0.0;
  EXPECT_EQ(message_of(c), "fusion.source_timeout_s = 0: must be in (0, 3600]");
  c = {};
  c.located_radius_m = -1.0;
  EXPECT_EQ(message_of(c), "fusion.located_radius_m = -1: must be in (0, 100]");
  c = {};
  c.merge_gate_probability = 0.0;
  EXPECT_EQ(message_of(c), "fusion.merge_gate_probability = 0: must be in (0, 1)");
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

SourceEstimate repeat_of(SourceEstimate s, responder::RepeatState state, std::uint32_t of) {
  s.repeat = state;
  s.repeat_of_signal = of;
  return s;
}

// a's signal 1 found, its signal 2 located 0.4 m away: two victims, as far as incident command knows.
void found_and_located_by_a(VictimFusion& f) {
  f.update(src("a", 1, kSec, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.update(src("a", 2, kSec, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kLocated));
  f.step(kSec);
}

// One transmitter split into two signals by a's separation: a's device cannot yet tell signal 2
// from signal 1, found. Signal 2 still shows where a second victim may be, but confirms nothing:
// its victim, located before, goes back to unconfirmed and names the victim it may be.
TEST(VictimFusion, ASuspectedRepeatConfirmsNothingAndNamesTheVictimItMayBe) {
  VictimFusion f;
  found_and_located_by_a(f);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kLocated) << "before the device's word";
  EXPECT_EQ(f.victims()[1].possibly_same_as, 0u);
  f.update(repeat_of(src("a", 2, 2 * kSec, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kConverged),
                     responder::RepeatState::kSuspected, 1));
  f.update(src("a", 1, 2 * kSec, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.step(2 * kSec);
  ASSERT_EQ(f.victims().size(), 2u) << "shown, as a possible second victim";
  EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
  EXPECT_EQ(f.victims()[1].state, VictimState::kUnconfirmed);
  EXPECT_EQ(f.victims()[1].located_at, 0);
  EXPECT_EQ(f.victims()[1].possibly_same_as, f.victims()[0].victim_id);
  // Another rescuer locating it there stands by it: the repeat's doubt is a's alone.
  f.update(src("b", 1, 3 * kSec, Vec3(0.45, 0.0, -1.0), 0.15, EstimatorStatus::kLocated));
  f.update(repeat_of(src("a", 2, 3 * kSec, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kConverged),
                     responder::RepeatState::kSuspected, 1));
  f.update(src("a", 1, 3 * kSec, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.step(3 * kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kLocated);
}

// A repeat claim counts while its estimator is heard: the core daemon's copy suspected signal 2,
// then stopped (killed); the device, which sees every sample, says none, and confirms it again.
TEST(VictimFusion, AStoppedEstimatorsRepeatClaimLapses) {
  VictimFusion f;
  found_and_located_by_a(f);
  SourceEstimate daemon = repeat_of(src("a", 2, 2 * kSec, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kConverged),
                                    responder::RepeatState::kSuspected, 1);
  daemon.from_device = false;
  daemon.estimator = "core";
  f.update(daemon);
  f.step(2 * kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kUnconfirmed) << "while the daemon suspects it";
  const TimestampNs later = 2 * kSec + static_cast<TimestampNs>(f.config().source_timeout_s * 1e9) + kSec;
  f.update(src("a", 1, later, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.update(src("a", 2, later, Vec3(0.4, 0.0, -1.0), 0.15, EstimatorStatus::kLocated));
  f.step(later);
  ASSERT_EQ(f.victims().size(), 2u);
  EXPECT_EQ(f.victims()[1].state, VictimState::kLocated);
  EXPECT_EQ(f.victims()[1].possibly_same_as, 0u);
}

// Stood over, signal 2 is signal 1 again: the victim it had opened merges into signal 1's.
TEST(VictimFusion, AConfirmedRepeatMergesItsVictimIntoTheVictimOfTheSignalItRepeats) {
  VictimFusion f;
  found_and_located_by_a(f);
  ASSERT_EQ(f.victims().size(), 2u);
  ASSERT_EQ(f.victims()[1].state, VictimState::kLocated);
  f.update(repeat_of(src("a", 2, 2 * kSec, Vec3(0.05, 0.0, -1.0), 0.1, EstimatorStatus::kConverged),
                     responder::RepeatState::kConfirmed, 1));
  f.update(src("a", 1, 2 * kSec, Vec3(0.0, 0.0, -1.0), 0.1, EstimatorStatus::kFound));
  f.step(2 * kSec);
  ASSERT_EQ(f.victims().size(), 1u);
  EXPECT_EQ(f.victims()[0].victim_id, 1u);
  EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
  EXPECT_EQ(f.take_removed(), (std::vector<std::uint32_t>{2}));
  // Its later estimates open nothing.
  f.update(repeat_of(src("a", 2, 3 * kSec, Vec3(0.05, 0.0, -1.0), 0.1, EstimatorStatus::kConverged),
                     responder::RepeatState::kConfirmed, 1));
  f.step(3 * kSec);
  EXPECT_EQ(f.victims().size(), 1u);
}

// Every rescuer's separation split one transmitter into two signals: one rescuer's signals
// never share a victim, so the picture holds two victims a few decimetres apart. It cannot tell
// them from one: neither is confirmed by the fused radius, each names the other, and only a
// device's own word confirms. Before, both were LOCATED (live, four within 5 m, clean seed 1:
// one victim confirmed twice, 0.56 m apart).
TEST(VictimFusion, ATransmitterEveryRescuerSplitIsNotConfirmedTwice) {
  VictimFusionConfig c;
  c.source_timeout_s = 5.0;
  VictimFusion f(c);
  const Vec3 a(-1.5, 39.0, -1.2);
  auto report = [&](TimestampNs t, EstimatorStatus r2_first, bool with_r2) {
    for (const char* r : {"r1", "r2", "r3"}) {
      if (!with_r2 && std::string(r) == "r2") continue;
      const bool first_of_r2 = std::string(r) == "r2";
      f.update(src(r, 1, t, a + Vec3(0.1, 0.0, 0.0), 0.15, first_of_r2 ? r2_first : EstimatorStatus::kConverged));
      f.update(src(r, 2, t, a + Vec3(-0.1, 0.1, 0.0), 0.15));
    }
    f.step(t);
  };
  report(0, EstimatorStatus::kConverged, true);
  ASSERT_EQ(f.victims().size(), 2u);
  for (const FusedVictim& v : f.victims()) {
    EXPECT_EQ(v.sources.size(), 3u);
    EXPECT_EQ(v.state, VictimState::kUnconfirmed) << "victim " << v.victim_id;
    EXPECT_NE(v.possibly_same_as, 0u);
    EXPECT_NE(v.possibly_same_as, v.victim_id);
  }
  // r2's device stands over its first signal: that victim is found, the other still names it.
  report(kSec, EstimatorStatus::kFound, true);
  ASSERT_EQ(f.victims().size(), 2u);
  const auto found = std::find_if(f.victims().begin(), f.victims().end(),
                                  [](const FusedVictim& v) { return v.state == VictimState::kFound; });
  ASSERT_NE(found, f.victims().end());
  const std::uint32_t found_id = found->victim_id;
  EXPECT_EQ(found->possibly_same_as, 0u);
  for (const FusedVictim& v : f.victims()) {
    if (v.victim_id == found_id) continue;
    EXPECT_EQ(v.state, VictimState::kUnconfirmed);
    EXPECT_EQ(v.possibly_same_as, found_id);
  }
  // r2 walks on (its sources time out): what its device found stays found.
  report(7 * kSec, EstimatorStatus::kConverged, false);
  const auto still = std::find_if(f.victims().begin(), f.victims().end(),
                                  [&](const FusedVictim& v) { return v.victim_id == found_id; });
  ASSERT_NE(still, f.victims().end());
  EXPECT_EQ(still->state, VictimState::kFound);
}

// r3's FOUND signal shares victim 1 with r2's estimate; r3's split of that transmitter appears
// next to r2's, outside the FOUND one's merge gate. Joint association would give the newcomer
// victim 1 (it fits r2's estimate better) and open a second victim for the FOUND signal: the
// device's FOUND keeps its victim. Before: victim 1 went on with the converged split, and C was
// FOUND twice (live, four within 5 m).
TEST(VictimFusion, ASignalItsDeviceLocatedKeepsItsVictimAgainstANewcomerOfTheSameRescuer) {
  VictimFusion f;
  const Vec3 c(0.0, 42.0, -1.0);
  auto report = [&](TimestampNs t, bool with_split) {
    f.update(src("r2", 3, t, c + Vec3(0.7, 0.9, 0.0), 0.4));
    f.update(src("r3", 3, t, c, 0.1, EstimatorStatus::kFound));
    if (with_split) f.update(src("r3", 5, t, c + Vec3(0.72, 0.96, 0.0), 0.3));
    f.step(t);
  };
  report(0, false);
  ASSERT_EQ(f.victims().size(), 1u);
  ASSERT_EQ(f.victims()[0].state, VictimState::kFound);
  report(kSec, true);
  report(2 * kSec, true);
  ASSERT_EQ(f.victims().size(), 2u);
  const FusedVictim& first = f.victims()[0];
  EXPECT_EQ(first.state, VictimState::kFound);
  ASSERT_EQ(first.sources.size(), 2u);
  EXPECT_TRUE(std::any_of(first.sources.begin(), first.sources.end(),
                          [](const VictimSource& s) { return s.rescuer_id == "r3" && s.signal_id == 3; }));
  EXPECT_EQ(f.victims()[1].state, VictimState::kUnconfirmed) << "the split confirms nothing";
}

// A victim located by the fused radius alone, then a twin: the same rescuers' second signals
// there. The confirmation rested on nothing a device said, and is withdrawn.
TEST(VictimFusion, AConfirmationByTheFusedRadiusAloneIsWithdrawnForATwin) {
  VictimFusion f;
  const Vec3 a(-1.5, 39.0, -1.2);
  f.update(src("r1", 1, 0, a, 0.15));
  f.update(src("r3", 1, 0, a + Vec3(0.05, 0.0, 0.0), 0.15));
  f.step(0);
  ASSERT_EQ(f.victims().size(), 1u);
  ASSERT_EQ(f.victims()[0].state, VictimState::kLocated) << "the fused radius";
  f.update(src("r1", 2, kSec, a + Vec3(0.2, 0.1, 0.0), 0.15));
  f.update(src("r3", 2, kSec, a + Vec3(0.25, 0.1, 0.0), 0.15));
  f.update(src("r1", 1, kSec, a, 0.15));
  f.update(src("r3", 1, kSec, a + Vec3(0.05, 0.0, 0.0), 0.15));
  f.step(kSec);
  ASSERT_EQ(f.victims().size(), 2u);
  for (const FusedVictim& v : f.victims()) {
    EXPECT_EQ(v.state, VictimState::kUnconfirmed) << "victim " << v.victim_id;
    EXPECT_EQ(v.located_at, 0);
    EXPECT_NE(v.possibly_same_as, 0u);
  }
}

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

SourceEstimate signed_by(SourceEstimate s, double carrier_hz, double period_s) {
  // As a device states it: its oscillator's 4.6 Hz in the carrier, the timing filter's period.
  s.transmitter = responder::TransmitterSignature{carrier_hz, 4.6, period_s, 0.0002};
  return s;
}

// The four-within-5m failure of the fresh-clone CI of a127f40: C FOUND by r1 and r2 in one
// victim, by r3 in a second one that r3's estimate had opened 1 m away; both then FOUND 0.56 m
// apart, and kept apart as two dig sites. Their signatures (one carrier within the devices'
// oscillators, one period) say one transmitter: one victim. Victims of distinct signatures, or
// of signatures not known, stay two (TwoFoundVictimsNeverMerge).
TEST(VictimFusion, TwoFoundVictimsOfOneTransmitterAreOne) {
  const Vec3 c(0.0, 42.0, -1.0), far = c + Vec3(3.0, 0.0, 0.0), near = c + Vec3(0.45, 0.3, 0.0);
  for (const double r3_carrier : {7.0, 45.0}) {  // r1's 3 Hz: the same transmitter, then another
    VictimFusion f;
    for (int k = 0; k < 6; ++k) {
      const TimestampNs t = k * kSec;
      f.update(signed_by(src("r1", 2, t, c, 0.35, EstimatorStatus::kFound), 3.0, 1.005));
      f.update(signed_by(src("r3", 4, t, k < 3 ? far : near, 0.35, EstimatorStatus::kFound), r3_carrier, 1.005));
      f.step(t);
      if (k == 2) {
        ASSERT_EQ(f.victims().size(), 2u) << "3 m apart: two victims";
      }
    }
    if (r3_carrier == 7.0) {
      ASSERT_EQ(f.victims().size(), 1u) << "one transmitter FOUND twice";
      EXPECT_EQ(f.victims()[0].state, VictimState::kFound);
      EXPECT_EQ(f.victims()[0].sources.size(), 2u);
      EXPECT_EQ(f.take_removed().size(), 1u);
    } else {
      ASSERT_EQ(f.victims().size(), 2u) << "two transmitters 0.54 m apart merged";
    }
  }
}

// Seen live (four-within-5m under load): r2's FOUND signal of A fell silent for 12 s (its pulses
// went to a new signal, a suspected repeat of it), the repeat took A's place beside r1's FOUND,
// and the FOUND signal, heard again, opened a second FOUND victim: A twice. A signal its device
// found comes back to the victim it was last bound to.
TEST(VictimFusion, AFoundSignalBackFromSilenceTakesItsVictimBackFromARepeat) {
  const Vec3 a(-1.5, 39.0, -1.2);
  VictimFusion f;
  TimestampNs t = 0;
  for (int k = 0; k < 3; ++k, t += kSec) {
    f.update(src("r1", 3, t, a, 0.35, EstimatorStatus::kFound));
    f.update(src("r2", 3, t, a + Vec3(0.4, 0.0, 0.0), 0.35, EstimatorStatus::kFound));
    f.step(t);
  }
  ASSERT_EQ(f.victims().size(), 1u);
  const TimestampNs silent_from = t;
  for (; t < silent_from + 12 * kSec; t += kSec) {  // r2/3 silent; r2/9 follows A, a suspected repeat
    f.update(src("r1", 3, t, a, 0.35, EstimatorStatus::kFound));
    f.update(repeat_of(src("r2", 9, t, a, 0.35, EstimatorStatus::kConverged), responder::RepeatState::kSuspected, 3));
    f.step(t);
  }
  ASSERT_EQ(f.victims().size(), 1u);
  ASSERT_EQ(f.victims()[0].sources.size(), 2u);
  EXPECT_EQ(f.victims()[0].sources[1].signal_id, 9u) << "the repeat in the silent signal's place";
  for (int k = 0; k < 3; ++k, t += kSec) {
    f.update(src("r1", 3, t, a, 0.35, EstimatorStatus::kFound));
    f.update(src("r2", 3, t, a + Vec3(0.4, 0.0, 0.0), 0.35, EstimatorStatus::kFound));
    f.update(repeat_of(src("r2", 9, t, a, 0.35, EstimatorStatus::kConverged), responder::RepeatState::kSuspected, 3));
    f.step(t);
  }
  std::size_t confirmed = 0;
  for (const FusedVictim& v : f.victims()) {
    if (v.state == VictimState::kUnconfirmed) continue;
    ++confirmed;
    ASSERT_EQ(v.sources.size(), 2u);
    EXPECT_EQ(v.sources[1].rescuer_id, "r2");
    EXPECT_EQ(v.sources[1].signal_id, 3u) << "the FOUND signal back in its victim";
  }
  EXPECT_EQ(confirmed, 1u) << "A twice";
}

// ---------------------------------------------------------------------------------------------
// The hard case: two victims 8 m apart, three rescuers each seeing both, GNSS error per
// rescuer (bias common to all its signals, slowly varying), estimate noise 0.2 m, signals
// converging at random times and in random order. Seed 001.
struct Mission {
  double gnss_h = 1.5, gnss_v = 2.5, est = 0.2;
  VictimFusionConfig config;
};

struct MissionResult {
  int draws = 0, count_ok = 0, association_ok = 0, inside95 = 0, victims = 0, within_1m = 0;
};

MissionResult run_missions(const Mission& m, int draws, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_int_distribution<int> converge_step(0, 12);
  const std::vector<Vec3> truth = {Vec3(0.0, 0.0, -1.5), Vec3(8.0, 0.0, -1.0)};
  const std::vector<std::string> rescuers = {"r1", "r2", "r3"};
  const Mat3 cov_g = Vec3(m.gnss_h * m.gnss_h, m.gnss_h * m.gnss_h, m.gnss_v * m.gnss_v).asDiagonal();
  const Mat3 cov = cov_g + m.est * m.est * Mat3::Identity();
  const double gate95 = chi_square_quantile(0.95, 3.0);
  MissionResult res;
  for (int d = 0; d < draws; ++d) {
    VictimFusion f(m.config);
    std::vector<Vec3> bias(rescuers.size());
    for (auto& b : bias) b = Vec3(m.gnss_h * n01(rng), m.gnss_h * n01(rng), m.gnss_v * n01(rng));
    // signal ids are the device's own: victim v is signal sig[r][v]; random convergence steps
    std::vector<std::vector<std::uint32_t>> sig(rescuers.size());
    std::vector<std::vector<int>> conv(rescuers.size());
    for (std::size_t r = 0; r < rescuers.size(); ++r) {
      const bool swap = n01(rng) > 0.0;
      sig[r] = swap ? std::vector<std::uint32_t>{2, 1} : std::vector<std::uint32_t>{1, 2};
      conv[r] = {converge_step(rng), converge_step(rng)};
    }
    bool always_le2 = true;
    constexpr int kSteps = 40;
    std::set<std::uint32_t> ids_at_20;
    bool ids_stable = true;
    for (int k = 0; k < kSteps; ++k) {
      const TimestampNs t = k * kSec;
      for (std::size_t r = 0; r < rescuers.size(); ++r) {
        // GNSS error: first-order Gauss-Markov, stationary sigma = the one declared (tau ~ 20 s)
        constexpr double kA = 0.95;
        const double q = std::sqrt(1.0 - kA * kA);
        bias[r] = kA * bias[r] + q * Vec3(m.gnss_h * n01(rng), m.gnss_h * n01(rng), m.gnss_v * n01(rng));
        for (std::size_t v = 0; v < truth.size(); ++v) {
          const Vec3 e = m.est * Vec3(n01(rng), n01(rng), n01(rng));
          const EstimatorStatus st = k >= conv[r][v] ? EstimatorStatus::kConverged
                                                     : EstimatorStatus::kMultimodal;
          SourceEstimate s;
          s.rescuer_id = rescuers[r];
          s.signal_id = sig[r][v];
          s.stamp = t;
          s.state = source_state_of(st);
          s.below_surface = true;
          s.position.position = truth[v] + bias[r] + e;
          s.position.covariance = cov;
          f.update(s);
        }
      }
      f.step(t);
      // Every signal has converged from step 13 on: never more than two victims from then.
      // (Before, a transient duplicate that the merge / ghost rule removes is tolerated: seen
      // in 1 of 100 draws with corrected GNSS, seed 002.)
      if (k > 12) always_le2 = always_le2 && f.victims().size() <= 2;
      std::set<std::uint32_t> ids;
      for (const FusedVictim& v : f.victims()) ids.insert(v.victim_id);
      if (k == 20) ids_at_20 = ids;
      if (k > 20 && ids != ids_at_20) ids_stable = false;
    }
    ++res.draws;
    if (always_le2 && ids_stable && f.victims().size() == 2) ++res.count_ok;
    bool assoc = f.victims().size() == 2;
    for (const FusedVictim& v : f.victims()) {
      // every source of this victim belongs to the same truth
      std::set<std::size_t> truths;
      for (const VictimSource& s : v.sources)
        for (std::size_t r = 0; r < rescuers.size(); ++r)
          if (rescuers[r] == s.rescuer_id)
            truths.insert(s.signal_id == sig[r][0] ? 0u : 1u);
      assoc = assoc && truths.size() == 1 && v.sources.size() == 3;
      if (truths.size() != 1) continue;
      const Vec3 err = v.position.position - truth[*truths.begin()];
      ++res.victims;
      if (err.dot(Eigen::LLT<Mat3>(v.position.covariance).solve(err)) <= gate95) ++res.inside95;
      if (err.norm() <= 1.0) ++res.within_1m;
    }
    if (assoc) ++res.association_ok;
  }
  return res;
}

TEST(VictimFusion, TwoVictimsEightMetresApartRealisticGnss) {
  Mission m;
  const MissionResult r = run_missions(m, 150, 1);
  // KNOWN LIMITATION (docs/estimation/incident-fusion.md, "Limits"): with 1.5 m GNSS per
  // rescuer the relative offset between two rescuers (sigma 2.1 m) is a quarter of the
  // separation, and pairwise gating mis-associates about 1 draw in 150 (seed 001). Fixing it
  // needs the per-rescuer common-offset registration described there. Tighten to == draws then.
  EXPECT_GE(r.count_ok, r.draws - 1);        // exactly two victims, never more, stable ids
  EXPECT_GE(r.association_ok, r.draws - 1);  // each victim holds the 3 right sources
  // Accuracy is bounded by GNSS: the mean of 3 rescuers has sigma 1.5/sqrt(3) = 0.87 m per
  // horizontal axis, so "<= 1 m" cannot hold for every draw here; consistency must.
  EXPECT_GE(r.inside95, static_cast<int>(0.95 * r.victims));
  RecordProperty("within_1m_fraction", std::to_string(double(r.within_1m) / r.victims));
}

TEST(VictimFusion, TwoVictimsEightMetresApartCorrectedGnssWithinOneMetre) {
  Mission m;
  m.gnss_h = 0.3;  // SBAS / RTK-class
  m.gnss_v = 0.4;
  const MissionResult r = run_missions(m, 100, 2);
  EXPECT_EQ(r.count_ok, r.draws);
  EXPECT_EQ(r.association_ok, r.draws);
  EXPECT_EQ(r.within_1m, r.victims);
  EXPECT_EQ(r.victims, 2 * r.draws);
}

}  // namespace
}  // namespace sarloc::incident
