// The SOG filter's update against the dense algorithm (EKF and iterated), the sign-invariant
// likelihood and invalid axes.
#include "sarloc/core/avalanche/sog_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sarloc/core/avalanche/odometry_accumulator.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sog_scenarios.hpp"

namespace sarloc::avalanche {
namespace {

using namespace test;  // sog_scenarios.hpp

// A filter of `components` unpruned, unmerged Gaussians, for checks against dense algebra (the
// paper's algorithm: no prior weights on top).
SogConfig dense_check_config(std::uint32_t components) {
  SogConfig cfg;
  cfg.initial_components = components;
  cfg.moment_constraint = false;
  cfg.prune_log_weight = 700.0;
  cfg.merge_interval = 0;
  cfg.use_orientation = false;
  return cfg;
}

// One step of a filter started from the scenario's first sample: the mixture before it, the
// displacement and the sample it took, and the step's result.
struct OneStep {
  SogFilter filter;
  std::vector<SogComponent> before;
  Displacement disp;
  FieldMeasurement meas;
  SogStepResult result;
};

OneStep one_step(const Scenario& scenario, std::uint64_t seed, const SogConfig& cfg, double bearing, double distance) {
  AvalancheSimulator sim(SimulationConfig{}, scenario, seed);
  OneStep one{SogFilter(cfg), {}, {}, {}, {}};
  one.filter.process(sim.measure());
  one.before = one.filter.components();
  const Odometry odo = sim.walk(bearing, distance);
  OdometryAccumulator acc(cfg.idle_translation_sigma_m, cfg.idle_rotation_sigma_rad);
  acc.add(odo);
  one.disp = acc.take();
  one.meas = sim.measure();
  one.filter.add_odometry(odo);
  one.result = one.filter.process(one.meas);
  return one;
}

// The filter's block-structured step (eq. (10)-(11), (14), (15), (17)) against Algorithm 1
// written densely on x* = [x; d]: P* = blkdiag(P, Q), one 3x15 H, the 15x15 EKF update, then
// P_k = F P*_post F^T with the 9x15 F. Pruning, merging and the attitude sensor are off so the
// components stay in order.
TEST(SogFilterTest, StepEqualsDenseAlgorithmOnTheAugmentedState) {
  SogConfig cfg = dense_check_config(120);
  cfg.iterated_update_max = 0;  // the plain EKF step (the iterated one: the next test)
  const OneStep one = one_step(fixed_scenario(), 11, cfg, 0.4, 1.0);
  const auto& [f, before, disp, meas, result] = one;
  ASSERT_EQ(result.dropped_numerical, 0u);
  ASSERT_EQ(f.size(), before.size());

  using AugCov = Eigen::Matrix<double, idx::kAugDim, idx::kAugDim>;
  const Vec3 floor = f.noise().floor(meas.noise_stddev);
  std::vector<double> log_w(before.size());
  double max_log_w = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < before.size(); ++i) {
    const SogComponent& c = before[i];
    AugVec xa;
    xa << c.x, disp.mean;
    AugCov pa = AugCov::Zero();
    pa.topLeftCorner<idx::kStateDim, idx::kStateDim>() = c.P;
    pa.bottomRightCorner<idx::kDispDim, idx::kDispDim>() = disp.covariance;
    Jacobian<3, idx::kAugDim> h;
    const Vec3 z_pred = MeasurementModel::h(xa, &h);
    const Vec3 sigma = Vec3::Constant(cfg.noise_relative * z_pred.norm()) + floor;
    const Mat3 s = h * pa * h.transpose() + Mat3(sigma.cwiseAbs2().asDiagonal());
    const Jacobian<idx::kAugDim, 3> k = pa * h.transpose() * s.inverse();
    const Vec3 nu = meas.field - z_pred;
    const AugVec xa_post = xa + k * nu;
    const AugCov pa_post = pa - k * s * k.transpose();
    Jacobian<idx::kStateDim, idx::kAugDim> fj;
    const StateVec x_expect = CompositionModel::f(xa_post, &fj);
    const StateCov p_expect = fj * pa_post * fj.transpose();
    const SogComponent& got = f.components()[i];
    EXPECT_LT((got.x - x_expect).norm(), 1e-9 * (1.0 + x_expect.norm())) << "component " << i;
    EXPECT_LT((got.P - p_expect).cwiseAbs().maxCoeff(), 1e-8 * p_expect.cwiseAbs().maxCoeff())
        << "component " << i;
    log_w[i] = c.log_weight - 0.5 * (nu.dot(s.inverse() * nu) + std::log(s.determinant()));
    max_log_w = std::max(max_log_w, log_w[i]);
  }
  double sum = 0.0;
  for (double v : log_w) sum += std::exp(v - max_log_w);
  for (std::size_t i = 0; i < before.size(); ++i)
    EXPECT_NEAR(f.components()[i].log_weight, log_w[i] - max_log_w - std::log(sum), 1e-8);
}

// The iterated update (SogConfig::iterated_update_max) against a dense Gauss-Newton on the
// augmented state [x; d], 2-3 m from the transmitter where the field is far from linear over a
// component's spread: same iterates, same stop rule, same posterior; the weights keep the
// prior-linearised likelihood.
TEST(SogFilterTest, IteratedStepEqualsDenseGaussNewtonOnTheAugmentedState) {
  Scenario near = fixed_scenario();
  near.transmitter = Vec3(1.6, 1.2, -1.2);
  const SogConfig cfg = dense_check_config(80);
  const OneStep one = one_step(near, 17, cfg, 0.3, 0.8);
  const auto& [f, before, disp, meas, result] = one;
  ASSERT_EQ(result.dropped_numerical, 0u);
  ASSERT_EQ(f.size(), before.size());

  using AugCov = Eigen::Matrix<double, idx::kAugDim, idx::kAugDim>;
  const Vec3 floor = f.noise().floor(meas.noise_stddev);
  auto noise = [&](const Vec3& h) {
    const Vec3 sigma = Vec3::Constant(cfg.noise_relative * h.norm()) + floor;
    return std::pair<Vec3, Mat3>(sigma, Mat3(sigma.cwiseAbs2().asDiagonal()));
  };
  int iterated = 0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const SogComponent& c = before[i];
    AugVec xa0;
    xa0 << c.x, disp.mean;
    AugCov pa = AugCov::Zero();
    pa.topLeftCorner<idx::kStateDim, idx::kStateDim>() = c.P;
    pa.bottomRightCorner<idx::kDispDim, idx::kDispDim>() = disp.covariance;
    Jacobian<3, idx::kAugDim> h_prev;
    Vec3 z_prev = MeasurementModel::h(xa0, &h_prev);
    Mat3 s = h_prev * pa * h_prev.transpose() + noise(z_prev).second;
    const double sign = meas.field.dot(s.inverse() * z_prev) >= 0.0 ? 1.0 : -1.0;
    const Vec3 z = sign * meas.field;
    Jacobian<idx::kAugDim, 3> k = pa * h_prev.transpose() * s.inverse();
    AugVec xa_prev = xa0;
    AugVec xa = xa0 + k * (z - z_prev);
    for (std::uint32_t it = 0; it < cfg.iterated_update_max; ++it) {
      Jacobian<3, idx::kAugDim> h_i;
      const Vec3 z_i = MeasurementModel::h(xa, &h_i);
      const auto [sigma, r_i] = noise(z_i);
      const Vec3 gap = (z_i - (z_prev + h_prev * (xa - xa_prev))).cwiseQuotient(sigma);
      if (gap.squaredNorm() <= cfg.relinearise_threshold_sigmas * cfg.relinearise_threshold_sigmas) break;
      if (it == 0) ++iterated;
      s = h_i * pa * h_i.transpose() + r_i;
      k = pa * h_i.transpose() * s.inverse();
      xa_prev = xa;
      z_prev = z_i;
      h_prev = h_i;
      xa = xa0 + k * (z - z_i - h_i * (xa0 - xa_prev));
    }
    const AugCov pa_post = pa - k * s * k.transpose();
    Jacobian<idx::kStateDim, idx::kAugDim> fj;
    const StateVec x_expect = CompositionModel::f(xa, &fj);
    const StateCov p_expect = fj * pa_post * fj.transpose();
    const SogComponent& got = f.components()[i];
    EXPECT_LT((got.x - x_expect).norm(), 1e-8 * (1.0 + x_expect.norm())) << "component " << i;
    EXPECT_LT((got.P - p_expect).cwiseAbs().maxCoeff(), 1e-7 * p_expect.cwiseAbs().maxCoeff())
        << "component " << i;
  }
  EXPECT_GT(iterated, 0) << "no component was re-linearised: the test would check nothing";
}

// A real receiver gives the field up to its sign: flipping the sign of any sample changes
// nothing in the posterior (sign-invariant likelihood).
TEST(SogFilterTest, SignOfTheFieldDoesNotMatter) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 3);
  SogFilter plain, flipped;
  std::mt19937_64 coin(4);
  for (int k = 0; k < 12; ++k) {
    FieldMeasurement z = sim.measure();
    plain.process(z);
    if (coin() % 2 == 0) z.field = -z.field;
    flipped.process(z);
    const Odometry o = sim.walk(bearing_to_truth(sim), 1.0);
    plain.add_odometry(o);
    flipped.add_odometry(o);
  }
  const VictimEstimate a = plain.estimate(), b = flipped.estimate();
  EXPECT_LT((a.relative.position - b.relative.position).norm(), 1e-9);
  EXPECT_LT((a.relative.covariance - b.relative.covariance).norm(), 1e-12);
}

// An invalid axis carries no information: its value is ignored by the update.
TEST(SogFilterTest, InvalidAxisIsIgnored) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 5);
  SogFilter a, b;
  for (int k = 0; k < 6; ++k) {
    FieldMeasurement z = sim.measure();
    if (k > 0) z.valid_axes = 0b101;
    a.process(z);
    if (k > 0) z.field.y() *= -7.0;  // garbage on the invalid axis
    b.process(z);
    const Odometry o = sim.walk(bearing_to_truth(sim), 1.0);
    a.add_odometry(o);
    b.add_odometry(o);
  }
  EXPECT_LT((a.estimate().relative.position - b.estimate().relative.position).norm(), 1e-9);
  FieldMeasurement beyond = sim.measure();
  beyond.valid_axes = 8;  // 0 is a pulse due and not heard (negative_information_test.cpp)
  EXPECT_THROW(a.process(beyond), InputError);
}

}  // namespace
}  // namespace sarloc::avalanche
