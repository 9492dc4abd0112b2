#include "sarloc/core/avalanche/simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/sensor_simulation.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {

TEST(SimulationConfigTest, RefusesNoiseBelowIssueMinimums) {
  EXPECT_NO_THROW(SimulationConfig{}.validate());
  auto expect_bad = [](auto mutate, const char* key) {
    SimulationConfig c;
    mutate(c);
    try {
      c.validate();
      ADD_FAILURE() << key;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  expect_bad([](SimulationConfig& c) { c.field_noise_relative = 0.04; }, "simulation.field_noise_relative");
  expect_bad([](SimulationConfig& c) { c.field_noise_floor_A_per_m = 1e-9; }, "simulation.field_noise_floor_A_per_m");
  expect_bad([](SimulationConfig& c) { c.odometry_translation_relative = 0.02; }, "odometry_translation_relative");
  expect_bad([](SimulationConfig& c) { c.odometry_yaw_sigma_deg = 0.9; }, "odometry_yaw_sigma_deg");
  expect_bad([](SimulationConfig& c) { c.odometry_roll_pitch_sigma_deg = 0.4; }, "odometry_roll_pitch_sigma_deg");
  expect_bad([](SimulationConfig& c) { c.start_distance_max_m = 10; }, "start_distance_max_m");
}

TEST(SimulatorTest, ScenarioDistributionsMatchTheIssue) {
  SimulationConfig c;
  int shallow = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    AvalancheSimulator sim(c, derive_seed(99, i));
    const Scenario& s = sim.scenario();
    const double d = sim.true_horizontal_distance();
    EXPECT_GE(d, 40.0);
    EXPECT_LE(d, 60.0);
    EXPECT_GE(s.moment.norm(), c.standard.moment_min() - 1e-12);
    EXPECT_LE(s.moment.norm(), c.standard.moment_max() + 1e-12);
    if (-s.transmitter.z() < 3.0) ++shallow;
  }
  EXPECT_NEAR(shallow / static_cast<double>(n), 0.95, 0.02);
}

// One burial draw for the single-victim simulator and the multiple burials: 95 % of the
// depths within burial_depth_p95_m, none above min_burial_depth_m; moments within the
// standard's range, in every direction.
TEST(SimulatorTest, BurialDepthsAndMomentsFollowTheirDistributions) {
  SimulationConfig c;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  constexpr int kDraws = 20000;
  int within_p95 = 0;
  Vec3 direction_sum = Vec3::Zero();
  for (int k = 0; k < kDraws; ++k) {
    const double depth = draw_burial_depth(c, rng, n01);
    ASSERT_GE(depth, c.min_burial_depth_m);
    if (depth <= c.burial_depth_p95_m) ++within_p95;
    const Vec3 m = draw_moment(c, rng, u01);
    ASSERT_GE(m.norm(), c.standard.moment_min() - 1e-12);
    ASSERT_LE(m.norm(), c.standard.moment_max() + 1e-12);
    direction_sum += m.normalized();
  }
  // Binomial(20000, 0.95): sd 0.0015.
  EXPECT_NEAR(static_cast<double>(within_p95) / kDraws, 0.95, 0.006);
  EXPECT_LT(direction_sum.norm() / kDraws, 0.03) << "no preferred direction";
}

TEST(SimulatorTest, FieldNoiseIsAtLeastTheRelativePlusFloorModel) {
  Scenario s;
  s.transmitter = Vec3(5, 0, -1);
  s.moment = Vec3(0, 0, 0.02);
  s.receiver = Vec3(0, 0, 1);
  AvalancheSimulator sim(SimulationConfig{}, s, 4);
  const Vec3 truth = DipoleField::field(s.receiver - s.transmitter, s.moment);
  const double sigma = 0.05 * truth.norm() + SimulationConfig{}.field_noise_floor_A_per_m;
  double sq = 0.0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) sq += (sim.measure().field - truth).squaredNorm();
  EXPECT_NEAR(std::sqrt(sq / (3.0 * n)) / sigma, 1.0, 0.05);
}

TEST(SimulatorTest, OdometryNoiseAndTurnFromTrueHeading) {
  Scenario s;
  s.transmitter = Vec3(50, 0, -1);
  s.moment = Vec3(0, 0, 0.02);
  s.receiver = Vec3(0, 0, 1);
  s.receiver_rpy = Vec3(0, 0, 0.3);
  AvalancheSimulator sim(SimulationConfig{}, s, 8);
  const Odometry o = sim.walk(0.5, 1.0);
  EXPECT_NEAR(sim.scenario().receiver_rpy.z(), 0.8, 1e-12);
  EXPECT_NEAR((sim.scenario().receiver - Vec3(std::cos(0.8), std::sin(0.8), 1)).norm(), 0.0, 1e-12);
  EXPECT_GE(std::sqrt(o.covariance(0, 0)), 0.03 - 1e-12);
  EXPECT_GE(std::sqrt(o.covariance(5, 5)), 1.0 * kPi / 180 - 1e-12);
  EXPECT_GE(std::sqrt(o.covariance(3, 3)), 0.5 * kPi / 180 - 1e-12);
  // Sample statistics of the yaw error over many steps.
  double sq = 0.0;
  const int n = 3000;
  for (int i = 0; i < n; ++i) {
    const Vec3 before = sim.scenario().receiver_rpy;
    const Odometry step = sim.walk(0.0, 1.0);
    const Mat3 rel = rotation_from_rpy(before).transpose() * rotation_from_rpy(sim.scenario().receiver_rpy);
    sq += std::pow(wrap_angle(step.rotation_rpy.z() - rpy_from_rotation(rel).z()), 2);
  }
  EXPECT_NEAR(std::sqrt(sq / n) * 180 / kPi, 1.0, 0.06);
}

}  // namespace
}  // namespace sarloc::avalanche
