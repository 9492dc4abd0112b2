// ZUPT-aided INS: the error-state transition against the propagation it linearises, standing
// still, the motionless alarm, bad samples, drift over a simulated walk, and a Monte Carlo
// consistency check of the displacement covariance.
#include "sarloc/core/firefighter/zupt_ins.hpp"

#include <gtest/gtest.h>

#include <random>

#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/firefighter/foot_trajectory.hpp"
#include "sarloc/core/firefighter/imu_error_model.hpp"
#include "support/numeric_jacobian.hpp"
#include "test_walks.hpp"

namespace sarloc::firefighter {
namespace {

using Vec15 = Eigen::Matrix<double, 15, 1>;

ImuSample sample(double t, const Eigen::Vector3d& f, const Eigen::Vector3d& w) {
  ImuSample s;
  s.t = t;
  s.specific_force = f;
  s.angular_rate = w;
  return s;
}

TEST(ZuptIns, TransitionMatchesTheNumericJacobianOfThePropagation) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  auto random3 = [&](double s) -> Eigen::Vector3d { return Eigen::Vector3d(n(rng), n(rng), n(rng)) * s; };
  for (int c = 0; c < 3; ++c) {  // zero, tiny and random motion
    const double scale = c == 0 ? 0.0 : (c == 1 ? 1e-6 : 1.0);
    ZuptIns::Nominal x;
    x.q = Eigen::Quaterniond(Eigen::AngleAxisd(scale * 0.7, Eigen::Vector3d(1, 2, 3).normalized()));
    x.v = random3(scale);
    x.ba = random3(0.05 * scale);
    x.bg = random3(0.01 * scale);
    const ImuSample s0 = sample(0.0, Eigen::Vector3d(0, 0, kGravity) + random3(3.0 * scale), random3(4.0 * scale));
    const ImuSample s1 = sample(0.01, Eigen::Vector3d(0, 0, kGravity) + random3(3.0 * scale), random3(4.0 * scale));
    const double dt = 0.01;
    const ZuptIns::Nominal y = ZuptIns::propagate(x, s0, s1, dt);
    const auto numeric = test::numeric_jacobian<15, 15>(
        [&](const Vec15& dx) { return ZuptIns::difference(ZuptIns::propagate(ZuptIns::inject(x, dx), s0, s1, dt), y); },
        Vec15::Zero(), 1e-6);
    const auto analytic = ZuptIns::transition(x, s0, s1, dt);
    EXPECT_LT(test::relative_error(analytic, numeric, 1e-9), 1e-5) << "case " << c << "\n" << analytic - numeric;
  }
}

TEST(ZuptIns, StandingStillStaysPutAndRaisesTheMotionlessAlarmAfterItsTime) {
  std::mt19937_64 rng(1);
  ImuErrors errors(ImuErrorConfig{}, rng);
  ZuptInsConfig config;
  config.motionless_after_s = 30.0;
  ZuptIns ins(config);
  const Eigen::Vector3d f(0.3, -0.2, std::sqrt(kGravity * kGravity - 0.13));
  for (int k = 0; k < 6000; ++k) {  // 60 s
    ins.push(errors.apply(sample(k * 0.01, f, Eigen::Vector3d::Zero()), rng));
    if (k == 2500) {
      EXPECT_FALSE(ins.motionless()) << "only 25 s still";
    }
  }
  EXPECT_TRUE(ins.aligned());
  EXPECT_TRUE(ins.motionless());
  EXPECT_LT(ins.take_displacement().delta.norm(), 0.05);
  // Moving again clears it at once.
  const Eigen::Vector3d kick(3.0, 0.0, kGravity), spin(0.0, 2.0, 0.0);
  ins.push(sample(60.0, kick, spin));
  EXPECT_FALSE(ins.motionless());
}

// The vote of SHOE, ARED and AMVD (StanceDetector::kVote): a boot pushed steadily, 2 m/s^2 more
// than gravity and not turning, is still for AMVD (no variance) and ARED (no rate) and moving for
// SHOE (its specific force is not gravity's): a stance for a vote of 2, not for SHOE alone or a
// unanimous vote. A boot turning at a steady 30 deg/s under gravity is still for AMVD alone.
TEST(ZuptIns, AVoteOfShoeAredAndAmvdDecidesTheStanceByItsCount) {
  const auto stationary = [](StanceDetector detector, std::uint32_t votes, const Eigen::Vector3d& f,
                             const Eigen::Vector3d& w) {
    ZuptInsConfig config;
    config.detector = detector;
    config.stance_votes = votes;
    ZuptIns ins(config);
    for (int k = 0; k < 10; ++k) ins.push(sample(k * 0.01, f, w));
    return ins.stationary();
  };
  const Eigen::Vector3d pushed(0.0, 0.0, kGravity + 2.0), upright(0.0, 0.0, kGravity);
  const Eigen::Vector3d turning(0.0, 0.0, 30.0 * kPi / 180.0);
  EXPECT_FALSE(stationary(StanceDetector::kShoe, 2, pushed, Eigen::Vector3d::Zero()));
  EXPECT_TRUE(stationary(StanceDetector::kVote, 2, pushed, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(stationary(StanceDetector::kVote, 3, pushed, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(stationary(StanceDetector::kVote, 2, upright, turning)) << "AMVD alone is no majority";
  EXPECT_TRUE(stationary(StanceDetector::kVote, 3, upright, Eigen::Vector3d::Zero())) << "all three: still";
  ZuptInsConfig bad;
  bad.stance_votes = 4;
  EXPECT_THROW(bad.validate(), ConfigError);
}

TEST(ZuptIns, RefusesBadSamplesNamingTheField) {
  ZuptIns ins(ZuptInsConfig{});
  const Eigen::Vector3d g(0, 0, kGravity);
  ins.push(sample(1.0, g, Eigen::Vector3d::Zero()));
  auto expect_error = [&](const ImuSample& s, const std::string& field) {
    try {
      ins.push(s);
      ADD_FAILURE() << "accepted " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  expect_error(sample(1.01, Eigen::Vector3d(NAN, 0, 9.81), Eigen::Vector3d::Zero()), "imu.specific_force");
  expect_error(sample(1.01, g, Eigen::Vector3d(0, INFINITY, 0)), "imu.angular_rate");
  expect_error(sample(1.01, Eigen::Vector3d(0, 0, 1e4), Eigen::Vector3d::Zero()), "16 g");
  expect_error(sample(1.0, g, Eigen::Vector3d::Zero()), "not after the previous sample");
  expect_error(sample(0.5, g, Eigen::Vector3d::Zero()), "not after the previous sample");
  ins.push(sample(1.01, g, Eigen::Vector3d::Zero()));  // and the filter still runs
  EXPECT_EQ(ins.time(), 1.01);
}

using walks::square_walk;

TEST(ZuptIns, DriftsLessThanOnePercentOverASimulatedWalkWithMti3Errors) {
  const FootTrajectory foot(square_walk(120));  // 96 m, about 200 s
  for (std::uint64_t seed : {1, 2, 3}) {
    std::mt19937_64 rng(seed);
    ImuErrors errors(ImuErrorConfig{}, rng);
    ZuptIns ins(ZuptInsConfig{});
    for (const ImuSample& s : foot.imu_samples(100.0)) ins.push(errors.apply(s, rng));
    const Eigen::Vector3d truth = foot.footfalls().back().position;
    EXPECT_LT((ins.nominal().p - truth).head<2>().norm(), 0.01 * 96.0) << "seed " << seed;
  }
}

// A real boot is switched on and walked at once: 0.3 s of standing is its first stance, aligned
// on (the gyro bias then comes from the standing parts of later stances); one that stands a
// second aligns at 1 s.
TEST(ZuptIns, AlignsOnASecondOfStillnessOrOnItsFirstStance) {
  for (const double standing_s : {0.3, 1.5}) {
    const FootTrajectory foot(square_walk(120, standing_s));
    std::mt19937_64 rng(7);
    ImuErrors errors(ImuErrorConfig{}, rng);
    ZuptIns ins(ZuptInsConfig{});
    double aligned_at = -1.0;
    for (const ImuSample& s : foot.imu_samples(100.0)) {
      ins.push(errors.apply(s, rng));
      if (ins.aligned() && aligned_at < 0.0) aligned_at = s.t;
    }
    ASSERT_GE(aligned_at, 0.0) << "standing " << standing_s << " s: never aligned";
    EXPECT_LE(aligned_at, std::min(standing_s, 1.0) + 0.1) << "standing " << standing_s << " s";
    const Eigen::Vector3d truth = foot.footfalls().back().position;
    EXPECT_LT((ins.nominal().p - truth).head<2>().norm(), 0.02 * 96.0) << "standing " << standing_s << " s";
  }
}

// A boot coasting at constant velocity reads gravity alone, as in a stance. Mid-swing, at 2 m/s,
// that is a pause, not a footfall: its ZUPT would stop the track there. A still reading that
// lasts swing_pause_max_s, or begins swing_max_s after the last stance, is a stance whatever the
// speed (after missed stances the INS's own velocity may be wrong by more than the gate).
TEST(ZuptIns, APauseInsideASwingIsNoStanceUnlessItLasts) {
  const auto walk = [](double coast_s, double landing_speed_max_mps, bool* stance_in_coast, double swing_max_s = 1.0) {
    ZuptInsConfig config;
    config.landing_speed_max_mps = landing_speed_max_mps;
    config.swing_max_s = swing_max_s;
    ZuptIns ins(config);
    const Eigen::Vector3d still(0.0, 0.0, kGravity), push(8.0, 0.0, kGravity), brake(-8.0, 0.0, kGravity);
    const Eigen::Vector3d no_turn = Eigen::Vector3d::Zero();
    double t = 0.0, x = 0.0, v = 0.0;  // the truth along x
    const auto run = [&](double seconds, const Eigen::Vector3d& f, bool coast) {
      for (int k = 0; k < static_cast<int>(std::lround(seconds * 100.0)); ++k) {
        t += 0.01;
        const double a = f.x();
        x += v * 0.01 + 0.5 * a * 0.0001;
        v += a * 0.01;
        ins.push(sample(t, f, no_turn));
        if (coast && ins.stationary()) *stance_in_coast = true;
      }
    };
    run(1.5, still, false);
    EXPECT_TRUE(ins.aligned());
    run(0.25, push, false);  // 2 m/s
    run(coast_s, still, true);
    run(0.25, brake, false);  // stopped
    run(0.5, still, false);
    return ins.nominal().p.x() - x;
  };
  bool stance = false;
  const double error = walk(0.08, 1.0, &stance);
  EXPECT_FALSE(stance) << "a 0.08 s pause at 2 m/s is no stance";
  EXPECT_LT(std::abs(error), 0.02);
  stance = false;
  const double ungated = walk(0.08, 0.0, &stance);
  EXPECT_TRUE(stance) << "without the gate the pause is a stance";
  EXPECT_GT(std::abs(ungated), 0.1) << "and its ZUPT stops the track short";
  stance = false;
  walk(0.3, 1.0, &stance);
  EXPECT_TRUE(stance) << "a still reading that lasts is a stance at any speed";
  stance = false;
  walk(0.08, 1.0, &stance, 0.2);
  EXPECT_TRUE(stance) << "so is one that begins later after the last stance than any swing lasts";
}

// The alignment measures the white noise of the still IMU where it takes the gyro bias: what a
// new sensor's source file would declare. Over 0.25 s at 400 Hz (100 samples a axis) the
// densities come within 25 % of the simulated sensor's; the bias within 4 sigma of its mean.
TEST(ZuptIns, MeasuresTheNoiseAtRestWhereItTakesTheGyroBias) {
  for (const std::uint64_t seed : {1, 2, 3}) {
    std::mt19937_64 rng(seed);
    ImuErrorConfig sensor;
    sensor.rate_hz = 400.0;
    ImuErrors errors(sensor, rng);
    ZuptInsConfig config;
    config.rate_hz = 400.0;
    ZuptIns ins(config);
    const Eigen::Vector3d f(0.3, -0.2, std::sqrt(kGravity * kGravity - 0.13));
    for (int k = 0; k < 420 && !ins.aligned(); ++k)
      ins.push(errors.apply(sample(k / 400.0, f, Eigen::Vector3d::Zero()), rng));
    ASSERT_TRUE(ins.aligned());
    EXPECT_NEAR(ins.rest_noise().accel_density, sensor.accel_noise_density, 0.25 * sensor.accel_noise_density) << seed;
    EXPECT_NEAR(ins.rest_noise().gyro_density, sensor.gyro_noise_density, 0.25 * sensor.gyro_noise_density) << seed;
  }
}

// The level floor holds the height of a flat walk, and a flight of stairs (0.34 m per stride)
// still climbs: a stance that far above the last is no level floor.
TEST(ZuptIns, HeightHoldsOnALevelFloorAndStairsStillClimb) {
  for (const double rise : {0.0, 0.34}) {
    const FootTrajectory foot(square_walk(40, 8.0, rise, 30));  // the last 10 strides climb
    std::mt19937_64 rng(11);
    ImuErrors errors(ImuErrorConfig{}, rng);
    ZuptIns ins(ZuptInsConfig{});
    for (const ImuSample& s : foot.imu_samples(100.0)) ins.push(errors.apply(s, rng));
    const double truth_z = foot.footfalls().back().position.z();
    EXPECT_NEAR(ins.nominal().p.z(), truth_z, rise > 0.0 ? 0.1 : 0.03) << "rise " << rise;
  }
}

// Seed 001's consistency test: over Monte Carlo runs the displacement's NEES must not exceed the
// chi-square upper bound (an INS that claims more than it knows would mislead the particle filter).
TEST(ZuptIns, DisplacementCovarianceIsNotOverconfidentMonteCarloNees) {
  const FootTrajectory foot(square_walk(40));
  constexpr int kRuns = 40;
  double nees_sum = 0.0;
  for (int r = 0; r < kRuns; ++r) {
    std::mt19937_64 rng(100 + r);
    ImuErrors errors(ImuErrorConfig{}, rng);
    ZuptInsConfig config;
    config.stride_noise_m2_per_m = 0.0;  // the filter's own covariance: the simulator is its model
    ZuptIns ins(config);
    bool started = false;
    for (const ImuSample& s : foot.imu_samples(100.0)) {
      ins.push(errors.apply(s, rng));
      if (ins.aligned() && !started) {
        (void)ins.take_displacement();
        started = true;
      }
    }
    const StepDisplacement d = ins.take_displacement();
    const Eigen::Vector2d e = d.delta.head<2>() - foot.footfalls().back().position.head<2>();
    nees_sum += e.dot(d.covariance.topLeftCorner<2, 2>().ldlt().solve(e));
  }
  const double mean = nees_sum / kRuns;
  const double upper = chi_square_quantile(0.975, 2.0 * kRuns) / kRuns;
  EXPECT_LT(mean, upper) << "mean NEES " << mean;
  EXPECT_GT(mean, 0.0);
}

// On real boots the filter's covariance is 1e4 times too small (docs/estimation/firefighter.md,
// "An honest covariance on real boots"): the stated one adds stride_noise_m2_per_m per metre
// walked, horizontally, and nothing else.
TEST(ZuptIns, StatedDisplacementCovarianceAddsTheStrideNoisePerMetreWalked) {
  const FootTrajectory foot(square_walk(8));
  std::mt19937_64 rng(7);
  ImuErrors errors(ImuErrorConfig{}, rng);
  ZuptInsConfig own, stated;
  own.stride_noise_m2_per_m = 0.0;
  stated.stride_noise_m2_per_m = 0.04;
  ZuptIns a(own), b(stated);
  for (const ImuSample& s : foot.imu_samples(100.0)) {
    const ImuSample noisy = errors.apply(s, rng);
    a.push(noisy);
    b.push(noisy);
  }
  const StepDisplacement da = a.take_displacement(), db = b.take_displacement();
  ASSERT_GT(da.delta.head<2>().norm(), 5.0);
  EXPECT_EQ(da.delta, db.delta);
  Eigen::Matrix3d added = Eigen::Matrix3d::Zero();
  added(0, 0) = added(1, 1) = 0.04 * db.delta.head<2>().norm();
  EXPECT_LT((db.covariance - da.covariance - added).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace sarloc::firefighter
