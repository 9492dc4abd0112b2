// The INS over a whole recording and its errors against loop and footprint truth: a simulated
// walk whose footfalls are known, turned and shifted as a published truth frame would be.
#include "sarloc/core/firefighter/ins_recording.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "sarloc/core/firefighter/foot_trajectory.hpp"
#include "sarloc/core/firefighter/imu_error_model.hpp"
#include "test_walks.hpp"

namespace sarloc::firefighter {
namespace {

// An out-and-back walk of `strides` strides east then the same west: a closed loop.
std::vector<Footfall> there_and_back(int strides) {
  return walks::stride_walk(2 * strides, 2.0, 0.6, [strides](int k) { return k < strides ? 0.0 : kPi; });
}

// The walk's 100 Hz samples with the simulated MTi-3's errors drawn from `seed`.
std::vector<ImuSample> noisy_samples(const FootTrajectory& foot, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  ImuErrors errors(ImuErrorConfig{}, rng);
  std::vector<ImuSample> samples;
  for (const ImuSample& s : foot.imu_samples(100.0)) samples.push_back(errors.apply(s, rng));
  return samples;
}

TEST(InsRecording, CountsFootprintsAndMeasuresLoopAndFootprintErrorsInTheTruthsFrame) {
  const FootTrajectory foot(there_and_back(20));
  const std::vector<ImuSample> samples = noisy_samples(foot, 5);
  const InsRecording run = run_ins(samples, ZuptInsConfig{});
  ASSERT_TRUE(run.aligned_at_s.has_value());
  EXPECT_LE(*run.aligned_at_s, 1.05);
  ASSERT_EQ(run.stances.size(), 41u) << "the start and 40 footfalls";
  EXPECT_NEAR(run.distance_m, 32.0, 0.3);
  const auto loop = loop_error(run);
  ASSERT_TRUE(loop.has_value());
  EXPECT_LT(loop->error_3d_m, 0.3);
  // The truth as a dataset publishes it: its own origin and axes (turned 40 degrees, shifted).
  const Eigen::Rotation2Dd turn(0.7);
  std::vector<Eigen::Vector2d> truth;
  for (const Footfall& f : foot.footfalls()) truth.push_back(Eigen::Vector2d(3.0, -2.0) + turn * f.position.head<2>());
  const auto f = footprint_errors(run, truth);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->compared, 40u);
  EXPECT_NEAR(f->truth_distance_m, 32.0, 1e-9);
  EXPECT_LT(f->rigid_rms_m, 0.3);
  EXPECT_LT(f->final_m, 0.6);
  // A track off by a metre at the end shows it.
  std::vector<Eigen::Vector2d> shifted = truth;
  shifted.back() += Eigen::Vector2d(1.0, 0.0);
  EXPECT_GT(footprint_errors(run, shifted)->rigid_max_m, 0.7);
}

// The stride consistency compares each stride with its stated covariance: the same walk with
// twice the stride noise has about half the NEES, and a footprint put 0.5 m off raises it by what
// that error weighs against the stated covariance.
TEST(InsRecording, StrideNeesWeighsEachStridesErrorByItsStatedCovariance) {
  const FootTrajectory foot(there_and_back(20));
  const std::vector<ImuSample> samples = noisy_samples(foot, 6);
  std::vector<Eigen::Vector2d> truth;
  for (const Footfall& f : foot.footfalls()) truth.push_back(f.position.head<2>());
  ZuptInsConfig config;
  config.stride_noise_m2_per_m = 0.01;
  const auto narrow = footprint_errors(run_ins(samples, config), truth);
  config.stride_noise_m2_per_m = 0.02;
  const auto wide = footprint_errors(run_ins(samples, config), truth);
  ASSERT_TRUE(narrow && wide);
  EXPECT_EQ(narrow->stride_pairs, 40u);
  EXPECT_EQ(narrow->stride_groups, 0u);
  EXPECT_NEAR(wide->stride_nees_mean / narrow->stride_nees_mean, 0.5, 0.05);
  EXPECT_LT(narrow->stride_nees_lower, narrow->stride_nees_upper);
  std::vector<Eigen::Vector2d> moved = truth;
  moved[10] += Eigen::Vector2d(0.0, 0.5);
  // Strides 10 and 11 each 0.5 m off against a stated variance of 0.02 x 0.8 m per axis.
  const double expected_rise = 2.0 * (0.5 * 0.5 / (0.02 * 0.8)) / 40.0;
  EXPECT_NEAR(footprint_errors(run_ins(samples, config), moved)->stride_nees_mean - wide->stride_nees_mean,
              expected_rise, 0.1 * expected_rise);
}

TEST(InsRecording, ARecordingThatNeverStandsStillSaysSoWithItsLongestStillSpell) {
  std::vector<ImuSample> samples;
  for (int k = 0; k < 500; ++k) {
    ImuSample s;
    s.t = 0.01 * k;
    s.specific_force = Eigen::Vector3d(3.0 * std::sin(0.3 * k), 0.0, kGravity);
    s.angular_rate = Eigen::Vector3d(0.0, 2.0 * std::cos(0.3 * k), 0.0);
    samples.push_back(s);
  }
  const InsRecording run = run_ins(samples, ZuptInsConfig{});
  EXPECT_FALSE(run.aligned_at_s.has_value());
  EXPECT_TRUE(run.track.empty());
  EXPECT_LT(run.longest_still_s, 0.15);
  EXPECT_FALSE(loop_error(run).has_value());
}

}  // namespace
}  // namespace sarloc::firefighter
