// The grid filter's motion model: the dead-reckoning error it tracks ([Psi, s]) against Monte
// Carlo paths drawn from the same odometry, and its diffusion, which must widen the cells'
// position covariance by exactly the variance it says it applied.
#include "sarloc/core/avalanche/grid_filter.hpp"

#include <gtest/gtest.h>

#include <random>

#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/simulator.hpp"

namespace sarloc::avalanche {
namespace {

constexpr int kSteps = 30;

responder::Odometry step_odometry(std::uint64_t sequence) {
  responder::Odometry o;
  o.sequence = sequence;
  o.translation = Vec3(1.0, 0.0, 0.0);
  o.rotation_rpy = Vec3(0.0, 0.0, 0.02);  // a gentle left curve
  o.covariance.setZero();
  o.covariance.diagonal() << 0.03 * 0.03, 0.03 * 0.03, 0.03 * 0.03, 0.0087 * 0.0087, 0.0087 * 0.0087, 0.0175 * 0.0175;
  return o;
}

// A pulse due and not heard, with a noise so large that no cell would have been heard: it moves
// the grid and weighs nothing.
FieldMeasurement uninformative_miss(std::uint64_t sequence) {
  FieldMeasurement m;
  m.sequence = sequence;
  m.valid_axes = 0;
  m.noise_stddev = Vec3::Constant(1.0);
  return m;
}

// The grid after its first sample (ideal receiver, a transmitter 8 m away).
GridFilter started_grid() {
  SimulationConfig sim_config;
  sim_config.receiver.kind = ReceiverKind::kIdeal;
  Scenario s;
  s.transmitter = Vec3(6.0, 5.0, -1.5);
  s.moment = Vec3(0.01, -0.005, 0.012);
  s.receiver = Vec3(0.0, 0.0, 1.0);
  s.receiver_rpy = Vec3(0.0, 0.0, 0.4);
  AvalancheSimulator sim(sim_config, s, 3);
  GridFilter f(SogConfig{}, GridFilterConfig{});
  FieldMeasurement first = sim.measure();
  first.sequence = 1;
  f.update(first);
  return f;
}

TEST(GridFilterTest, DriftCovarianceMatchesMonteCarloPaths) {
  GridFilter f = started_grid();
  const MixtureMoments start = f.moments();
  const Vec3 psi0 = start.mean.segment<3>(idx::kAtt);
  const Mat3 psi_cov = start.covariance.block<3, 3>(idx::kAtt, idx::kAtt);
  for (int k = 0; k < kSteps; ++k) {
    f.add_odometry(step_odometry(k + 1));
    f.update(uninformative_miss(k + 2));
  }
  // The receiver's position after the walk, drawn from the same initial attitude and odometry.
  const responder::Odometry o = step_odometry(1);
  const Eigen::LLT<Mat6> odo_llt(o.covariance + Mat6::Identity() * 1e-18);
  const Mat3 psi_root = Eigen::LLT<Mat3>(psi_cov).matrixL();
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  auto normal3 = [&] { return Vec3(n01(rng), n01(rng), n01(rng)); };
  constexpr int kPaths = 6000;
  std::vector<Vec3> ends;
  Vec3 mean = Vec3::Zero();
  for (int path = 0; path < kPaths; ++path) {
    Mat3 r = rotation_from_rpy(psi0 + psi_root * normal3());
    Vec3 position = Vec3::Zero();
    for (int k = 0; k < kSteps; ++k) {
      Vec6 d;
      d << o.translation, o.rotation_rpy;
      Vec6 w;
      w << normal3(), normal3();
      d += odo_llt.matrixL() * w;
      position += r * d.head<3>();
      r = r * rotation_from_rpy(d.tail<3>());
    }
    ends.push_back(position);
    mean += position;
  }
  mean /= kPaths;
  Mat3 cov = Mat3::Zero();
  for (const Vec3& e : ends) cov += (e - mean) * (e - mean).transpose();
  cov /= kPaths - 1;
  // s = -(the receiver's error): the same covariance. The linearised error model against the
  // sampled paths: within 10 % (the sample variance's own spread is about 2 %) on the horizontal
  // axes, which carry the heading's metres.
  const Mat3 drift = f.drift_covariance();
  for (int a = 0; a < 2; ++a) EXPECT_NEAR(drift(a, a), cov(a, a), 0.1 * cov(a, a)) << "axis " << a;
  EXPECT_NEAR(drift(0, 1), cov(0, 1), 0.1 * std::sqrt(cov(0, 0) * cov(1, 1)));
  EXPECT_GT(cov(0, 0) + cov(1, 1), 1.0);  // metres of drift: worth modelling
  // The diffusion trails the drift by less than a tenth of a cell's variance.
  const double threshold = 0.1 * f.cell_m() * f.cell_m();
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(f.diffused_variance()[a], drift(a, a) + 1e-12) << "axis " << a;
    EXPECT_GT(f.diffused_variance()[a], drift(a, a) - threshold) << "axis " << a;
  }
}

TEST(GridFilterTest, DiffusionWidensThePositionByTheVarianceApplied) {
  GridFilter f = started_grid();
  const MixtureMoments before = f.moments();
  const Vec3 diffused_before = f.diffused_variance();
  for (int k = 0; k < kSteps; ++k) {
    f.add_odometry(step_odometry(k + 1));
    f.update(uninformative_miss(k + 2));
  }
  const MixtureMoments after = f.moments();
  const Vec3 applied = f.diffused_variance() - diffused_before;
  ASSERT_GT(applied.head<2>().minCoeff(), 0.1);
  const Mat3 p0 = before.covariance.block<3, 3>(idx::kPos, idx::kPos);
  const Mat3 p1 = after.covariance.block<3, 3>(idx::kPos, idx::kPos);
  // Each pass of the kernel [a, 1 - 2a, a] adds 2 a cell^2 to its axis and nothing across axes;
  // only the cells it spreads below the pruning threshold are lost.
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(p1(a, a) - p0(a, a), applied[a], 1e-3 * (1.0 + applied[a])) << "axis " << a;
  EXPECT_NEAR(p1(0, 1), p0(0, 1), 1e-3 * std::sqrt(p0(0, 0) * p0(1, 1)));
  // The mean moved by the dead-reckoned walk (the transmitter relative to the receiver).
  const Vec3 moved = after.mean.segment<3>(idx::kPos) - before.mean.segment<3>(idx::kPos);
  EXPECT_GT(moved.norm(), 0.8 * kSteps);
  EXPECT_LT(moved.norm(), 1.0 * kSteps);
}

}  // namespace
}  // namespace sarloc::avalanche
