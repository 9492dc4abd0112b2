// The firefighter pipeline as the live system runs it, without DDS: the device's INS turns the
// boot's IMU into 2 Hz odometry (FirefighterDevice), the daemon's estimator chains it into the
// map-aided filter (FirefighterEstimator) and answers with incident-frame positions; the
// device raises and clears its alarms and dead reckons from the last fix.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/estimator/estimator_journal.hpp"
#include "sarloc/core/estimator/firefighter_device.hpp"
#include "sarloc/core/estimator/make_estimator.hpp"
#include "sarloc/core/firefighter/foot_trajectory.hpp"
#include "sarloc/core/firefighter/imu_error_model.hpp"
#include "sarloc/core/firefighter/search_walk.hpp"
#include "support/config_messages.hpp"
#include "test_buildings.hpp"

namespace sarloc::estimator {
namespace {

using firefighter::FootTrajectory;
using firefighter::Footfall;

constexpr TimestampNs kOrigin = 1'700'000'000'000'000'000;
constexpr double kPi = 3.14159265358979323846;

double seconds(TimestampNs stamp) { return 1e-9 * static_cast<double>(stamp - kOrigin); }

EstimatorConfigs configs_for(const std::string& building, const std::string& responder, const std::string& entry,
                             firefighter::Vec2 origin = firefighter::Vec2::Zero(), double rotation_deg = 0.0) {
  EstimatorConfigs c;
  c.firefighter.building =
      std::make_shared<const firefighter::BuildingModel>(firefighter::test::building(building), firefighter::BuildingModelConfig{});
  c.firefighter.origin = origin;
  c.firefighter.rotation_deg = rotation_deg;
  if (!entry.empty()) c.firefighter.entry_of[responder] = {entry, firefighter::Hand::kRight};
  c.validate();
  return c;
}

// Straight strides along +x with a stop of `stop_s` after `before` strides.
std::vector<Footfall> walk_with_stop(int before, double stop_s, int after) {
  std::vector<Footfall> feet;
  Footfall start;
  start.stance_s = 8.0;
  feet.push_back(start);
  double t = 8.0, x = 0.0;
  for (int k = 0; k < before + after; ++k) {
    x += 0.8;
    Footfall f;
    f.t_land = t + 0.7;
    f.stance_s = k == before - 1 ? stop_s : 0.9;
    f.position = Eigen::Vector3d(x, 0.0, 0.0);
    feet.push_back(f);
    t = f.t_land + f.stance_s;
  }
  return feet;
}

struct LiveRun {
  std::vector<double> error_m;       // per answer, after the first minute
  std::size_t answers = 0, outside99 = 0, converged = 0;
  std::size_t confirmed = 0, confirmed_outside99 = 0;
  // Ambiguous answers, those whose places all miss the truth (99 %), and answers that broke the
  // candidates' protocol (places without the flag or the flag without places, two "ended" in a
  // row, a stamp not the position's, weights that do not sum to at most 1).
  std::size_t ambiguous = 0, ambiguous_truth_in_none = 0, ended = 0, protocol_broken = 0;
};

bool within99(const GaussianPosition& p, const firefighter::Vec2& truth) {
  const Eigen::Vector2d err = p.position.head<2>() - truth;
  const Eigen::Matrix2d P = p.covariance.topLeftCorner<2, 2>() + 1e-9 * Eigen::Matrix2d::Identity();
  return err.dot(P.ldlt().solve(err)) <= 9.21;  // chi2_2(0.99)
}

// A right-hand search of `plan` and the boot that walks it: the device turns its simulated
// MTi-3 samples (errors.apply) into 2 Hz odometry.
struct BootWalk {
  static std::vector<Footfall> leader_of(const firefighter::FloorPlan& plan, double duration_s, std::mt19937_64& rng) {
    firefighter::SearchWalkConfig walk;
    walk.duration_s = duration_s;
    return firefighter::generate_search_walk(plan, walk, firefighter::Hand::kRight, rng).leader;
  }
  static FirefighterDeviceConfig device_config() {
    FirefighterDeviceConfig c;
    c.ins.initial_yaw_rad = 0.0;
    return c;
  }
  BootWalk(const firefighter::FloorPlan& plan, std::uint64_t seed, double duration_s)
      : rng(seed),
        foot(leader_of(plan, duration_s, rng)),
        errors(firefighter::ImuErrorConfig{}, rng),
        device("ff1", "alpha", device_config(), kOrigin) {}
  std::mt19937_64 rng;
  FootTrajectory foot;
  firefighter::ImuErrors errors;
  FirefighterDevice device;
};

// One right-hand search of `building` from its first entry, IMU to estimator.
LiveRun run_search(const std::string& building, const std::string& entry, std::uint64_t seed,
                   firefighter::Vec2 origin = firefighter::Vec2::Zero(), double rotation_deg = 0.0,
                   std::uint64_t first_step = 1, bool* started_mid_search = nullptr, bool device_hints = false) {
  const EstimatorConfigs configs = configs_for(building, "ff1", entry, origin, rotation_deg);
  BootWalk boot(configs.firefighter.building->plan(), seed, 150.0);
  auto& [rng, foot, errors, device] = boot;
  auto estimator = make_estimator(ResponderRole::kFirefighter, "ff1", configs);
  const Eigen::Rotation2Dd R(rotation_deg * kPi / 180.0);
  LiveRun run;
  bool was_ambiguous = false;
  for (const auto& ideal : foot.imu_samples(100.0)) {
    device.push(errors.apply(ideal, rng));
    const auto odometry = device.take_odometry();
    if (device_hints && odometry && odometry->sequence + 4 >= first_step) {
      // The device: anchored by the last daemon's fix 2 s before this one came, then its own
      // reckoning once a second, as sarloc-rescuer publishes it.
      if (!device.dead_reckoning()) {
        responder::ResponderPosition fix;
        fix.responder_id = "ff1";
        fix.stamp = odometry->interval_end;
        const firefighter::Vec2 at = origin + R * foot.at(seconds(odometry->interval_end)).position.head<2>();
        fix.position.position = Vec3(at.x(), at.y(), 0.0);
        fix.position.covariance = 0.09 * Mat3::Identity();
        fix.heading_rad = rotation_deg * kPi / 180.0 + foot.at(seconds(odometry->interval_end)).yaw;
        fix.source = responder::PositionSource::kMapAided;
        fix.converged = true;
        device.on_fix(fix);
      } else if (odometry->sequence % 2 == 0) {
        estimator->hint_position(*device.dead_reckoning());
      }
    }
    if (!odometry || odometry->sequence < first_step) continue;  // a daemon that came later saw none of these
    auto outcome = estimator->add_odometry(*odometry);
    const auto* out = std::get_if<EstimatorOutput>(&outcome);
    EXPECT_NE(out, nullptr);
    if (out == nullptr || !out->position) continue;
    ++run.answers;
    const auto& p = *out->position;
    EXPECT_EQ(p.source, responder::PositionSource::kMapAided);
    const double t = seconds(p.stamp);
    const firefighter::Vec2 truth = origin + R * foot.at(t).position.head<2>();
    const Eigen::Vector2d err = p.position.position.head<2>() - truth;
    const Eigen::Matrix2d P = p.position.covariance.topLeftCorner<2, 2>() + 1e-9 * Eigen::Matrix2d::Identity();
    const bool outside = err.dot(P.ldlt().solve(err)) > 9.21;  // chi2_2(0.99)
    if (t > 60.0) run.error_m.push_back(err.norm());
    if (p.converged) {
      ++run.converged;
      run.outside99 += outside ? 1 : 0;
    }
    if (p.confirmed) {
      ++run.confirmed;
      run.confirmed_outside99 += outside ? 1 : 0;
    }
    if (out->candidates) {
      const auto& c = *out->candidates;
      double total = 0.0;
      for (const auto& place : c.candidates) total += place.weight;
      const bool named = c.candidates.size() >= 2 && c.candidates.size() <= 4;
      if (c.stamp != p.stamp || c.responder_id != "ff1" || total > 1.0 + 1e-9 || p.ambiguous != named ||
          (p.converged && named)) {
        ++run.protocol_broken;
      }
      if (c.candidates.empty()) {
        ++run.ended;
        if (!was_ambiguous) ++run.protocol_broken;  // an end of nothing
      }
    } else if (p.ambiguous || was_ambiguous) {
      ++run.protocol_broken;  // the places missing, or their end not said
    }
    if (p.ambiguous && out->candidates) {
      ++run.ambiguous;
      bool in_one = false;  // horizontally: the buildings tested here have one floor
      for (const auto& place : out->candidates->candidates) in_one = in_one || within99(place.position, truth);
      run.ambiguous_truth_in_none += in_one ? 0 : 1;
    }
    was_ambiguous = p.ambiguous;
  }
  if (started_mid_search != nullptr) {
    *started_mid_search = dynamic_cast<const FirefighterEstimator&>(*estimator).started_mid_search();
  }
  return run;
}

double rms(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}

TEST(FirefighterLive, FromTheReportedEntryTheDaemonTracksTheSearchInTheIncidentFrame) {
  // The building turned by 30 deg and moved: the answers must be in the incident frame.
  for (std::uint64_t seed : {1, 2, 3}) {
    const LiveRun run = run_search("house-125", "front", seed, {100.0, -40.0}, 30.0);
    ASSERT_GT(run.answers, 250U) << "2 Hz over 155 s";
    EXPECT_LT(rms(run.error_m), 1.0) << "seed " << seed;
    EXPECT_GT(run.confirmed, run.answers / 2) << "seed " << seed << ": a known entry's track is confirmed";
    EXPECT_LE(run.confirmed_outside99, run.confirmed / 50 + 1) << "seed " << seed;
  }
}

TEST(FirefighterLive, ADaemonMeetingTheFirefighterMidSearchDoesNotStartItAtTheReportedDoor) {
  // A core daemon restarted 60 s into the search: the first odometry it sees is step 121.
  for (std::uint64_t seed : {1, 2}) {
    bool mid_search = false;
    const LiveRun run = run_search("house-125", "front", seed, {}, 0.0, 121, &mid_search);
    EXPECT_TRUE(mid_search) << "seed " << seed;
    ASSERT_GT(run.answers, 150U);
    EXPECT_LE(run.confirmed_outside99, run.confirmed / 50 + 1) << "seed " << seed << ": " << run.confirmed << " confirmed";
  }
}

// Issue 65: a daemon that meets the firefighter mid-search starts near his device's own dead
// reckoning (anchored by the last daemon's fix) instead of anywhere in the building.
TEST(FirefighterLive, ADaemonMeetingTheFirefighterMidSearchStartsNearHisDevicesReckoning) {
  for (const auto& [building, entry] : {std::pair{"house-125", "front"}, {"warehouse-1040", "south"}}) {
    for (std::uint64_t seed : {1, 2}) {
      bool mid_search = false;
      const LiveRun run = run_search(building, entry, seed, {}, 0.0, 121, &mid_search, true);
      const LiveRun blind = run_search(building, entry, seed, {}, 0.0, 121, nullptr, false);
      std::printf(
          "%s seed %llu: with hints RMSE %.2f m, converged %zu of %zu, outside %zu; without RMSE %.2f m, converged "
          "%zu, outside %zu\n",
          building, static_cast<unsigned long long>(seed), rms(run.error_m), run.converged, run.answers, run.outside99,
          rms(blind.error_m), blind.converged, blind.outside99);
      EXPECT_TRUE(mid_search);
      EXPECT_LT(rms(run.error_m), 1.0) << building << " seed " << seed;
      EXPECT_GT(run.converged, run.answers * 9 / 10) << building << " seed " << seed;
      EXPECT_LE(run.outside99, run.converged / 50 + 1) << building << " seed " << seed;
      EXPECT_EQ(run.confirmed, 0U) << "only an entry confirms";
    }
  }
}

// What the daemon takes for a start: the newest dead reckoning of this firefighter, fresh and
// narrow enough; anything else leaves the start unknown (anywhere in the building).
TEST(FirefighterLive, OnlyAFreshNarrowReckoningOfThisFirefighterIsAStart) {
  const EstimatorConfigs configs = configs_for("house-125", "ff1", "front");
  responder::ResponderPosition good;
  good.responder_id = "ff1";
  good.stamp = kOrigin + 60'000'000'000;
  good.position.position = Vec3(3.0, 5.0, 0.0);
  good.position.covariance = 0.25 * Mat3::Identity();
  good.source = responder::PositionSource::kDeadReckoning;
  const auto starts_near = [&](const std::vector<responder::ResponderPosition>& hints) {
    FirefighterEstimator estimator("ff1", configs.firefighter);
    for (const auto& h : hints) estimator.hint_position(h);
    responder::Odometry o;
    o.rescuer_id = "ff1";
    o.sequence = 121;  // mid-search: the device's 121st step
    o.interval_start = good.stamp + 500'000'000;
    o.interval_end = o.interval_start + 500'000'000;
    EXPECT_TRUE(std::holds_alternative<EstimatorOutput>(estimator.add_odometry(o)));
    return estimator.started_near_hint();
  };
  EXPECT_FALSE(starts_near({}));
  EXPECT_TRUE(starts_near({good}));
  auto wide = good;
  wide.position.covariance = 9.0 * Mat3::Identity();  // 3 m: 3.25 m with the half second since
  EXPECT_FALSE(starts_near({wide}));
  auto stale = good;
  stale.stamp -= 20'000'000'000;
  EXPECT_FALSE(starts_near({stale}));
  auto other = good;
  other.responder_id = "ff2";
  EXPECT_FALSE(starts_near({other}));
  auto fix = good;
  fix.source = responder::PositionSource::kMapAided;  // the daemon's own, not the device's
  EXPECT_FALSE(starts_near({fix}));
  auto upstairs = good;
  upstairs.floor = 5;  // house-125 has one floor
  EXPECT_FALSE(starts_near({upstairs}));
  EXPECT_TRUE(starts_near({stale, good})) << "the newest counts";
  EXPECT_TRUE(starts_near({good, stale})) << "an older one after it changes nothing";
}

TEST(FirefighterLive, UnknownStartClaimsNothingItCannotBackUp) {
  const LiveRun run = run_search("house-125", "", 4);
  ASSERT_GT(run.answers, 250U);
  EXPECT_LE(run.confirmed_outside99, run.confirmed / 50 + 1);
}

// Issue 65: a cloud between look-alike corridors is neither converged nor shown as one place:
// the position says "ambiguous", each answer names the places with their weights, and the
// step that ends it says so once. On the warehouse from an unknown start (20000 particles).
TEST(FirefighterLive, AnAmbiguousPositionNamesItsPlacesAndSaysWhenItEnds) {
  std::size_t ambiguous = 0, in_none = 0;
  for (std::uint64_t seed : {1, 2}) {
    const LiveRun run = run_search("warehouse-1040", "", seed);
    EXPECT_EQ(run.protocol_broken, 0U) << "seed " << seed;
    EXPECT_LE(run.ended, run.ambiguous) << "seed " << seed;
    ambiguous += run.ambiguous;
    in_none += run.ambiguous_truth_in_none;
    std::printf("seed %llu: %zu answers, %zu ambiguous (truth in none of the places: %zu), %zu ends, %zu converged\n",
                static_cast<unsigned long long>(seed), run.answers, run.ambiguous, run.ambiguous_truth_in_none,
                run.ended, run.converged);
  }
  ASSERT_GT(ambiguous, 10U) << "these walks no longer show an ambiguous cloud";
  EXPECT_LE(in_none, ambiguous / 10);
}

TEST(FirefighterLive, EstimatorRefusesBadOdometryAndSensorSamplesLeavingItUntouched) {
  const EstimatorConfigs configs = configs_for("house-125", "ff1", "front");
  auto est = make_estimator(ResponderRole::kFirefighter, "ff1", configs);
  responder::Odometry o;
  o.rescuer_id = "ff1";
  o.sequence = 1;
  o.interval_start = kOrigin;
  o.interval_end = kOrigin + 500'000'000;
  o.translation = Vec3(0.3, 0.0, 0.0);
  o.source = responder::OdometrySource::kFootMountedIns;
  ASSERT_TRUE(std::holds_alternative<EstimatorOutput>(est->add_odometry(o)));
  const auto refused = [&](responder::Odometry bad, responder::RejectReason reason) {
    auto outcome = est->add_odometry(bad);
    const auto* r = std::get_if<responder::Rejection>(&outcome);
    ASSERT_NE(r, nullptr);
    EXPECT_EQ(r->reason, reason) << r->detail;
    EXPECT_NE(r->detail.find("ff1"), std::string::npos) << r->detail;
  };
  refused(o, responder::RejectReason::kDuplicateSequence);
  responder::Odometry next = o;
  next.sequence = 2;
  next.interval_start = o.interval_end;
  next.interval_end = o.interval_end + 500'000'000;
  auto nan = next;
  nan.translation.x() = std::nan("");
  refused(nan, responder::RejectReason::kInvalidValue);
  auto far = next;
  far.translation = Vec3(50.0, 0.0, 0.0);
  refused(far, responder::RejectReason::kAbsurdMotion);
  auto backwards = next;
  backwards.interval_start = o.interval_start;
  refused(backwards, responder::RejectReason::kStampBackwards);
  auto other = next;
  other.rescuer_id = "ff2";
  refused(other, responder::RejectReason::kWrongRescuer);
  const auto before = dynamic_cast<const FirefighterEstimator&>(*est).localizer().estimate().position;
  const auto good = est->add_odometry(next);
  const auto* answer = std::get_if<EstimatorOutput>(&good);
  ASSERT_NE(answer, nullptr) << "the good step after the bad ones";
  EXPECT_LT((answer->position->position.position.head<2>() - before).norm(), 1.0);
  avalanche::FieldMeasurement field;
  field.rescuer_id = "ff1";
  const auto wrong = est->process(SensorSample{field});
  ASSERT_TRUE(std::holds_alternative<responder::Rejection>(wrong));
  EXPECT_EQ(std::get<responder::Rejection>(wrong).reason, responder::RejectReason::kWrongRole);
}

TEST(FirefighterLive, ConfigNamesAnUnknownEntryAndAMissingBuilding) {
  EstimatorConfigs c = configs_for("house-125", "ff1", "front");
  c.firefighter.entry_of["ff1"].entry = "back";
  EXPECT_NE(sarloc::test::validation_error(c).find("rescuers[ff1].entry = 'back'"), std::string::npos)
      << sarloc::test::validation_error(c);
  EstimatorConfigs none;
  EXPECT_THROW(make_estimator(ResponderRole::kFirefighter, "ff1", none), ConfigError);
}

TEST(FirefighterLive, MotionlessAlarmFiresAfterItsTimeAndClearsWhenTheFirefighterMovesAgain) {
  std::mt19937_64 rng(5);
  const FootTrajectory foot(walk_with_stop(10, 45.0, 10));
  firefighter::ImuErrors errors(firefighter::ImuErrorConfig{}, rng);
  FirefighterDeviceConfig config;
  config.ins.motionless_after_s = 30.0;
  FirefighterDevice device("ff1", "alpha", config, kOrigin);
  // The stop: the 10th footfall lands and stays 45 s.
  const double stop_start = foot.footfalls()[10].t_land;
  const double stop_end = stop_start + 45.0;
  std::vector<responder::ResponderAlarm> changes;
  for (const auto& ideal : foot.imu_samples(100.0)) {
    device.push(errors.apply(ideal, rng));
    (void)device.take_odometry();
    for (auto& a : device.alarm_changes()) changes.push_back(a);
  }
  ASSERT_EQ(changes.size(), 2U) << "raised once, cleared once";
  EXPECT_EQ(changes[0].kind, responder::AlarmKind::kMotionless);
  EXPECT_TRUE(changes[0].active);
  const double raised = seconds(changes[0].raised_at);
  EXPECT_GE(raised, stop_start + 30.0 - 0.5);
  EXPECT_LE(raised, stop_start + 30.0 + 1.0) << "within its timeout plus one second";
  EXPECT_FALSE(changes[1].active);
  EXPECT_NEAR(seconds(changes[1].cleared_at), stop_end, 1.0) << "cleared by moving again";
  EXPECT_EQ(changes[1].raised_at, changes[0].raised_at);
}

TEST(FirefighterLive, ResetClearsAndReArmsTheMotionlessAlarmAndOnlyResetClearsAMayday) {
  std::mt19937_64 rng(6);
  const FootTrajectory foot(walk_with_stop(4, 80.0, 6));
  firefighter::ImuErrors errors(firefighter::ImuErrorConfig{}, rng);
  FirefighterDevice device("ff1", "alpha", FirefighterDeviceConfig{}, kOrigin);
  const double stop_start = foot.footfalls()[4].t_land;
  std::vector<responder::ResponderAlarm> changes;
  bool reset_done = false, mayday_pressed = false;
  for (const auto& ideal : foot.imu_samples(100.0)) {
    device.push(errors.apply(ideal, rng));
    if (!mayday_pressed && ideal.t > 9.0) {
      device.press_mayday();
      mayday_pressed = true;
    }
    if (!reset_done && ideal.t > stop_start + 35.0) {
      device.reset(responder::AlarmKind::kMotionless);
      reset_done = true;
    }
    for (auto& a : device.alarm_changes()) changes.push_back(a);
  }
  // mayday raised; motionless raised (~30 s), reset (35 s), raised again 30 s after the reset
  // (65 s), cleared by walking (80 s). The mayday is still active at the end: walking does not
  // clear it.
  std::vector<std::pair<responder::AlarmKind, bool>> seen;
  for (const auto& a : changes) seen.emplace_back(a.kind, a.active);
  const std::vector<std::pair<responder::AlarmKind, bool>> expected{
      {responder::AlarmKind::kMayday, true},      {responder::AlarmKind::kMotionless, true},
      {responder::AlarmKind::kMotionless, false}, {responder::AlarmKind::kMotionless, true},
      {responder::AlarmKind::kMotionless, false}};
  EXPECT_EQ(seen, expected);
  ASSERT_EQ(changes.size(), 5U);
  EXPECT_NEAR(seconds(changes[3].raised_at), stop_start + 65.0, 1.0);
  ASSERT_EQ(device.active_alarms().size(), 1U);
  EXPECT_EQ(device.active_alarms()[0].kind, responder::AlarmKind::kMayday);
  device.reset(responder::AlarmKind::kMayday);
  EXPECT_TRUE(device.active_alarms().empty());
}

TEST(FirefighterLive, DeadReckoningFromTheLastFixFollowsTheWalkWithinItsGrownUncertainty) {
  std::mt19937_64 rng(7);
  const FootTrajectory foot(walk_with_stop(5, 1.0, 40));  // 36 m along +x
  firefighter::ImuErrors errors(firefighter::ImuErrorConfig{}, rng);
  FirefighterDevice device("ff1", "alpha", FirefighterDeviceConfig{}, kOrigin);
  // The INS frame's x is the boot's heading at power-up (+x); in the incident frame the walk
  // heads north-east from (10, 20).
  const double heading = 0.25 * kPi;
  const Eigen::Rotation2Dd R(heading);
  bool fixed = false;
  EXPECT_FALSE(device.dead_reckoning()) << "no fix yet";
  for (const auto& ideal : foot.imu_samples(100.0)) {
    device.push(errors.apply(ideal, rng));
    const auto o = device.take_odometry();
    if (!o || fixed || seconds(o->interval_end) < 15.0) continue;
    responder::ResponderPosition fix;
    fix.responder_id = "ff1";
    fix.stamp = o->interval_end;
    const Eigen::Vector2d at = Eigen::Vector2d(10.0, 20.0) + R * foot.at(seconds(o->interval_end)).position.head<2>();
    fix.position.position = Vec3(at.x(), at.y(), 0.0);
    fix.position.covariance = 0.04 * Mat3::Identity();
    fix.heading_rad = heading + device.ins().yaw();
    fix.source = responder::PositionSource::kMapAided;
    device.on_fix(fix);
    fixed = true;
  }
  const auto p = device.dead_reckoning();
  ASSERT_TRUE(p);
  EXPECT_EQ(p->source, responder::PositionSource::kDeadReckoning);
  const double t = seconds(p->stamp);
  const Eigen::Vector2d truth = Eigen::Vector2d(10.0, 20.0) + R * foot.at(t).position.head<2>();
  const Eigen::Vector2d err = p->position.position.head<2>() - truth;
  EXPECT_LT(err.norm(), 3.0 * std::sqrt(p->position.covariance(0, 0))) << "error " << err.norm();
  EXPECT_GT(p->position.covariance(0, 0), 0.04 + 0.1) << "grown with the ~30 m walked";
  EXPECT_GT(device.distance_walked_m(), 30.0);
}

// The device's loop and the latency bench both start a device at its reported entry and publish
// its own position once a mission second: one implementation of each, here. The entry anchors
// dead reckoning at the INS's first pose (where the boot aligned), before any odometry, and the
// own positions come one a second under the device's ids, the entry's uncertainty grown by the walk.
TEST(FirefighterLive, ADeviceStartedAtItsEntryReckonsFromItsFirstPoseAndGivesItsOwnPositionOnceASecond) {
  std::mt19937_64 rng(9);
  const FootTrajectory foot(walk_with_stop(5, 1.0, 40));  // 36 m along +x from (0, 0)
  firefighter::ImuErrors errors(firefighter::ImuErrorConfig{}, rng);
  FirefighterDevice device("ff1", "alpha", FirefighterDeviceConfig{}, kOrigin);
  responder::ResponderPosition entry;
  entry.responder_id = "someone else";  // the device's own ids win
  entry.position.position = Vec3(10.0, 20.0, 0.0);
  entry.position.covariance = 0.09 * Mat3::Identity();
  entry.heading_rad = 0.0;  // the boot faces +x of the incident frame, as it walks
  entry.source = responder::PositionSource::kManual;
  ASSERT_TRUE(device.start_at(entry));
  EXPECT_FALSE(device.dead_reckoning()) << "not before the INS has aligned";
  std::vector<responder::ResponderPosition> own;
  std::optional<TimestampNs> first_odometry_start, aligned_at;
  for (const auto& ideal : foot.imu_samples(100.0)) {
    device.push(errors.apply(ideal, rng));
    if (device.aligned() && !aligned_at) {
      aligned_at = device.now();
      // Anchored in the push that started the INS, before any odometry: an alarm raised now
      // already carries the entry.
      const auto at_start = device.dead_reckoning();
      ASSERT_TRUE(at_start) << "not anchored when the INS started";
      EXPECT_EQ(at_start->stamp, *aligned_at);
      EXPECT_EQ(at_start->position.position, entry.position.position);
    }
    const auto o = device.take_odometry();
    if (!o) continue;
    if (!first_odometry_start) first_odometry_start = o->interval_start;
    if (auto p = device.take_own_position()) own.push_back(*p);
  }
  ASSERT_TRUE(first_odometry_start);
  EXPECT_EQ(*first_odometry_start, *aligned_at) << "the first odometry starts at the anchored pose";
  ASSERT_GT(own.size(), 20U);
  for (std::size_t i = 1; i < own.size(); ++i) {
    const double gap = seconds(own[i].stamp) - seconds(own[i - 1].stamp);
    EXPECT_GE(gap, 1.0 - 1e-9) << "position " << i;
    EXPECT_LE(gap, 1.5 + 1e-9) << "position " << i << ": one at the first odometry step past the second";
  }
  for (const auto& p : own) {
    EXPECT_EQ(p.responder_id, "ff1");
    EXPECT_EQ(p.team_id, "alpha");
    EXPECT_EQ(p.source, responder::PositionSource::kDeadReckoning);
  }
  // The entry's heading 0 turns the INS frame's yaw at its stamp onto +x: the walk heads
  // along +x from (10, 20) up to the INS's heading error at alignment.
  const auto& last = own.back();
  const Eigen::Vector2d truth = Eigen::Vector2d(10.0, 20.0) + foot.at(seconds(last.stamp)).position.head<2>() -
                                foot.at(seconds(*first_odometry_start)).position.head<2>();
  const double err = (last.position.position.head<2>() - truth).norm();
  EXPECT_GT(last.position.covariance(0, 0), 0.09 + 0.1) << "grown with the ~36 m walked";
  EXPECT_LT(err, 3.0 * std::sqrt(last.position.covariance(0, 0))) << "error " << err;
}

// An entry given after the INS started is taken at its first pose while the history reaches
// back to it, and refused (false) once it does not; a position that is not finite is refused
// by start_at itself, never inside push().
TEST(FirefighterLive, AnEntryIsTakenAtTheFirstPoseOnlyWhileTheHistoryHoldsItAndNeverIfNotFinite) {
  std::mt19937_64 rng(10);
  const FootTrajectory foot(walk_with_stop(5, 1.0, 20));
  firefighter::ImuErrors errors(firefighter::ImuErrorConfig{}, rng);
  FirefighterDeviceConfig config;
  config.history_s = 5.0;
  FirefighterDevice early("ff1", "alpha", config, kOrigin), late("ff1", "alpha", config, kOrigin);
  responder::ResponderPosition entry;
  entry.position.position = Vec3(10.0, 20.0, 0.0);
  entry.position.covariance = 0.09 * Mat3::Identity();
  entry.source = responder::PositionSource::kManual;
  responder::ResponderPosition broken = entry;
  broken.heading_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(early.start_at(broken), InputError);
  bool early_taken = false;
  std::optional<bool> late_taken;
  for (const auto& ideal : foot.imu_samples(100.0)) {
    const auto sample = errors.apply(ideal, rng);
    early.push(sample);
    late.push(sample);
    (void)early.take_odometry();
    (void)late.take_odometry();
    if (early.aligned() && !early_taken) {
      early_taken = true;
      EXPECT_TRUE(early.start_at(entry)) << "the INS has just started: its first pose is in the history";
      ASSERT_TRUE(early.dead_reckoning());
    }
    if (late.aligned() && !late_taken && late.distance_walked_m() > 10.0) late_taken = late.start_at(entry);
  }
  ASSERT_TRUE(late_taken);
  EXPECT_FALSE(*late_taken) << "the first pose left the 5 s history: no anchor at a later pose";
  EXPECT_FALSE(late.dead_reckoning());
}

// A daemon restarted mid-search first answers with the mean of a cloud spread over the plan. The
// device keeps dead reckoning from its surer anchor through those answers, and takes a fix again
// once it is surer or has converged (the kill-core building mission: docs/estimation/firefighter.md).
TEST(FirefighterLive, ADeviceKeepsItsReckoningAgainstAFixThatHasNotConvergedAndIsNotSurer) {
  std::mt19937_64 rng(8);
  const FootTrajectory foot(walk_with_stop(5, 1.0, 40));  // 36 m along +x from (0, 0)
  firefighter::ImuErrors errors(firefighter::ImuErrorConfig{}, rng);
  FirefighterDevice device("ff1", "alpha", FirefighterDeviceConfig{}, kOrigin);
  struct Offered {
    double at_s;
    Eigen::Vector2d off;  // from the truth
    double variance;
    bool converged, confirmed;
  };
  const std::vector<Offered> offered{
      {12.0, {0.0, 0.0}, 0.04, true, false},       // the first: taken
      {20.0, {15.0, -12.0}, 100.0, false, false},  // the restarted daemon's spread cloud: not surer
      {24.0, {0.0, 0.0}, 0.01, false, false},      // not converged, but surer: taken
      {28.0, {3.0, 0.0}, 4.0, false, true},        // not converged, wider: not taken
      {31.0, {2.0, 0.0}, 4.0, true, false},        // converged, however wide: taken
  };
  std::vector<bool> anchored;
  for (const auto& ideal : foot.imu_samples(100.0)) {
    device.push(errors.apply(ideal, rng));
    const auto o = device.take_odometry();
    if (!o || anchored.size() == offered.size()) continue;
    const Offered& next = offered[anchored.size()];
    const double t = seconds(o->interval_end);
    if (t < next.at_s) continue;
    const Eigen::Vector2d truth = foot.at(t).position.head<2>();
    const auto before = device.dead_reckoning();
    responder::ResponderPosition fix;
    fix.responder_id = "ff1";
    fix.stamp = o->interval_end;
    fix.position.position = Vec3(truth.x() + next.off.x(), truth.y() + next.off.y(), 0.0);
    fix.position.covariance = next.variance * Mat3::Identity();
    fix.heading_rad = device.ins().yaw();  // the incident frame is the INS frame here
    fix.source = responder::PositionSource::kMapAided;
    fix.converged = next.converged;
    fix.confirmed = next.confirmed;
    const bool taken = device.on_fix(fix);
    anchored.push_back(taken);
    const auto after = device.dead_reckoning();
    ASSERT_TRUE(after);
    if (taken) {
      EXPECT_NEAR((after->position.position - fix.position.position).norm(), 0.0, 0.05) << "at " << t << " s";
    } else {
      EXPECT_NEAR((after->position.position - before->position.position).norm(), 0.0, 1e-9) << "at " << t << " s";
    }
  }
  EXPECT_EQ(anchored, (std::vector<bool>{true, false, true, false, true}));
}

// Issue 64, item 4: a firefighter handed from one sector's daemon to another's keeps his filter
// (20000 particles from an unknown start, their generator included): the new daemon replays the
// old one's journal and answers as it would have, to the last bit.
TEST(FirefighterLive, ADaemonResumingTheJournalAnswersAsTheOldOneWouldHave) {
  const EstimatorConfigs configs = configs_for("house-125", "ff1", "");  // unknown start
  BootWalk boot(configs.firefighter.building->plan(), 4, 120.0);
  auto& [rng, foot, errors, device] = boot;
  JournaledEstimator first(make_estimator(ResponderRole::kFirefighter, "ff1", configs), 100000);
  std::unique_ptr<JournaledEstimator> second;
  std::size_t compared = 0, hints = 0;
  for (const auto& ideal : foot.imu_samples(100.0)) {
    device.push(errors.apply(ideal, rng));
    const auto odometry = device.take_odometry();
    if (!odometry) continue;
    if (odometry->sequence == 100) second = resume_estimator(first.journal(), configs, 100000);
    if (odometry->sequence % 40 == 0) {  // a position hint now and then, journaled too
      responder::ResponderPosition own;
      own.responder_id = "ff1";
      own.stamp = odometry->interval_end;
      own.position.position = Vec3(2.0, 3.0, 0.0);
      own.position.covariance = 4.0 * Mat3::Identity();
      own.source = responder::PositionSource::kDeadReckoning;
      first.hint_position(own);
      if (second) second->hint_position(own);
      ++hints;
    }
    const Outcome a = first.add_odometry(*odometry);
    if (!second) continue;
    const Outcome b = second->add_odometry(*odometry);
    const auto* x = std::get_if<EstimatorOutput>(&a);
    const auto* y = std::get_if<EstimatorOutput>(&b);
    ASSERT_TRUE(x != nullptr && y != nullptr) << "odometry " << odometry->sequence;
    ASSERT_EQ(x->position.has_value(), y->position.has_value());
    if (!x->position) continue;
    ++compared;
    EXPECT_EQ(x->position->position.position, y->position->position.position) << "odometry " << odometry->sequence;
    EXPECT_EQ(x->position->position.covariance, y->position->position.covariance) << "odometry " << odometry->sequence;
    EXPECT_EQ(x->position->converged, y->position->converged);
    EXPECT_EQ(x->position->ambiguous, y->position->ambiguous);
    EXPECT_EQ(x->candidates.has_value(), y->candidates.has_value());
  }
  EXPECT_GT(compared, 100U) << "2 Hz for the last 70 s";
  EXPECT_GT(hints, 3U);
  // The journal of a firefighter: one odometry a half second and the odd hint.
  std::printf("journal: %zu entries after %zu odometry steps\n", first.journal().entries.size(), compared + 99);
}

}  // namespace
}  // namespace sarloc::estimator
