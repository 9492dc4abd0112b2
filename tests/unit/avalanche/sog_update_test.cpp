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
  // The realistic receiver's tolerances, carried as consider parameters: the checks cover their terms.
  cfg.calibration_gain_sigma = 0.03;
  cfg.calibration_pointing_sigma_deg = 1.0;
  return cfg;
}

// One step of a filter started from the scenario's first sample and `warmup` steps after it (so
// that the mixture's cross-covariances with the calibration errors are not zero): the mixture
// before it, the displacement and the sample it took, and the step's result.
struct OneStep {
  SogFilter filter;
  std::vector<SogComponent> before;
  Displacement disp;
  FieldMeasurement meas;
  SogStepResult result;
};

OneStep one_step(const Scenario& scenario, std::uint64_t seed, const SogConfig& cfg, double bearing, double distance,
                 int warmup = 0) {
  AvalancheSimulator sim(SimulationConfig{}, scenario, seed);
  OneStep one{SogFilter(cfg), {}, {}, {}, {}};
  one.filter.process(sim.measure());
  for (int k = 0; k < warmup; ++k) {
    one.filter.add_odometry(sim.walk(bearing, distance));
    one.filter.process(sim.measure());
  }
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

// The dense check's state: x** = [x; d; E], the receiver's calibration errors E appended as
// consider parameters (zero mean, never estimated: every linearisation is at E = 0), so that one
// update of x** equals the filter's Schmidt-Kalman step in x and Cov(x, E).
constexpr int kDenseDim = idx::kAugDim + kCalibrationDim;
using DenseVec = Eigen::Matrix<double, kDenseDim, 1>;
using DenseCov = Eigen::Matrix<double, kDenseDim, kDenseDim>;

// x** and P** of component c before the update: P** = [[P, 0, C], [0, Q, 0], [C^T, 0, Sigma_E]].
std::pair<DenseVec, DenseCov> dense_prior(const SogComponent& c, const Displacement& disp, const SogConfig& cfg) {
  DenseVec xa = DenseVec::Zero();
  xa << c.x, disp.mean, CalibrationVec::Zero();
  DenseCov pa = DenseCov::Zero();
  pa.topLeftCorner<idx::kStateDim, idx::kStateDim>() = c.P;
  pa.block<idx::kDispDim, idx::kDispDim>(idx::kStateDim, idx::kStateDim) = disp.covariance;
  pa.block<idx::kStateDim, kCalibrationDim>(0, idx::kAugDim) = c.calibration_cross;
  pa.block<kCalibrationDim, idx::kStateDim>(idx::kAugDim, 0) = c.calibration_cross.transpose();
  pa.bottomRightCorner<kCalibrationDim, kCalibrationDim>() = cfg.calibration_variance().asDiagonal();
  return {xa, pa};
}

// z = (I + E) h(x, d) at E = 0 and its 3 x 24 Jacobian [H_x H_d H_E], written out densely, for
// the field the receiver resolves at wavenumber k.
Vec3 dense_h(const DenseVec& xa, Jacobian<3, kDenseDim>& h, double k) {
  Jacobian<3, idx::kAugDim> h_aug;
  const Vec3 z = MeasurementModel::h(AugVec(xa.head<idx::kAugDim>()), &h_aug, k);
  h.setZero();
  h.leftCols<idx::kAugDim>() = h_aug;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) h(a, idx::kAugDim + 3 * a + b) = z[b];  // dz_a / dE(a, b) = h_b
  return z;
}

// The composition of x** (eq. (9), (15)): the component's x, P and Cov(x, E) after the step.
struct Composed {
  StateVec x;
  StateCov P;
  CalibrationCross cross;
};
Composed dense_compose(const DenseVec& xa, const DenseCov& pa) {
  Jacobian<idx::kStateDim, idx::kAugDim> fj;
  Composed out;
  out.x = CompositionModel::f(AugVec(xa.head<idx::kAugDim>()), &fj);
  out.P = fj * pa.topLeftCorner<idx::kAugDim, idx::kAugDim>() * fj.transpose();
  out.cross = fj * pa.topRightCorner<idx::kAugDim, kCalibrationDim>();
  return out;
}

// The covariances are differences of nearly equal products (P - K S K^T): their rounding
// differs between an x86-64 and an aarch64 build (fused multiply-adds) by up to about 1e-7 of
// their largest entry after an iterated update; a wrong term is off by order one.
void expect_component(const SogComponent& got, const Composed& expect, double tolerance, std::size_t i) {
  EXPECT_LT((got.x - expect.x).norm(), tolerance * (1.0 + expect.x.norm())) << "component " << i;
  EXPECT_LT((got.P - expect.P).cwiseAbs().maxCoeff(), 100 * tolerance * expect.P.cwiseAbs().maxCoeff())
      << "component " << i;
  EXPECT_LT((got.calibration_cross - expect.cross).cwiseAbs().maxCoeff(),
            100 * tolerance * expect.cross.cwiseAbs().maxCoeff() + 1e-300)
      << "component " << i;
}

// The filter's block-structured step (eq. (10)-(11), (14), (15), (17)) against Algorithm 1
// written densely on x** = [x; d; E]: P** as in dense_prior, one 3x24 H, the 24x24 EKF update,
// then P_k = F P**_post F^T with the 9x15 F. Taken after two steps, so that the cross-covariance
// with the calibration errors is not zero. Pruning, merging and the attitude sensor are off so
// the components stay in order.
TEST(SogFilterTest, StepEqualsDenseAlgorithmOnTheAugmentedState) {
  SogConfig cfg = dense_check_config(120);
  cfg.iterated_update_max = 0;  // the plain EKF step (the iterated one: the next test)
  const OneStep one = one_step(fixed_scenario(), 11, cfg, 0.4, 1.0, 2);
  const auto& [f, before, disp, meas, result] = one;
  ASSERT_EQ(result.dropped_numerical, 0u);
  ASSERT_EQ(f.size(), before.size());

  const Vec3 floor = f.noise().floor(meas.noise_stddev);
  std::vector<double> log_w(before.size());
  double max_log_w = -std::numeric_limits<double>::infinity();
  double largest_cross = 0.0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const SogComponent& c = before[i];
    largest_cross = std::max(largest_cross, c.calibration_cross.cwiseAbs().maxCoeff());
    const auto [xa, pa] = dense_prior(c, disp, cfg);
    Jacobian<3, kDenseDim> h;
    const Vec3 z_pred = dense_h(xa, h, cfg.wavenumber());
    const Vec3 sigma = Vec3::Constant(cfg.noise_relative * z_pred.norm()) + floor;
    const Mat3 s = h * pa * h.transpose() + Mat3(sigma.cwiseAbs2().asDiagonal());
    const Jacobian<kDenseDim, 3> k = pa * h.transpose() * s.inverse();
    const Vec3 nu = meas.field - z_pred;
    expect_component(f.components()[i], dense_compose(xa + k * nu, pa - k * s * k.transpose()), 1e-9, i);
    log_w[i] = c.log_weight - 0.5 * (nu.dot(s.inverse() * nu) + std::log(s.determinant()));
    max_log_w = std::max(max_log_w, log_w[i]);
  }
  double sum = 0.0;
  for (double v : log_w) sum += std::exp(v - max_log_w);
  for (std::size_t i = 0; i < before.size(); ++i)
    EXPECT_NEAR(f.components()[i].log_weight, log_w[i] - max_log_w - std::log(sum), 1e-8);
  EXPECT_GT(largest_cross, 0.0) << "no cross-covariance with the calibration: the check would miss its terms";
}

// The iterated update (SogConfig::iterated_update_max) against a dense Gauss-Newton on the
// augmented state [x; d; E] (E held at 0: considered, never estimated), 2-3 m from the
// transmitter where the field is far from linear over a component's spread: same iterates, same
// stop rule, same posterior; the weights keep the prior-linearised likelihood.
TEST(SogFilterTest, IteratedStepEqualsDenseGaussNewtonOnTheAugmentedState) {
  Scenario near = fixed_scenario();
  near.transmitter = Vec3(1.6, 1.2, -1.2);
  const SogConfig cfg = dense_check_config(80);
  const OneStep one = one_step(near, 17, cfg, 0.3, 0.8);
  const auto& [f, before, disp, meas, result] = one;
  ASSERT_EQ(result.dropped_numerical, 0u);
  ASSERT_EQ(f.size(), before.size());

  const Vec3 floor = f.noise().floor(meas.noise_stddev);
  auto noise = [&](const Vec3& h) {
    const Vec3 sigma = Vec3::Constant(cfg.noise_relative * h.norm()) + floor;
    return std::pair<Vec3, Mat3>(sigma, Mat3(sigma.cwiseAbs2().asDiagonal()));
  };
  int iterated = 0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const SogComponent& c = before[i];
    const auto [xa0, pa] = dense_prior(c, disp, cfg);
    Jacobian<3, kDenseDim> h_prev;
    Vec3 z_prev = dense_h(xa0, h_prev, cfg.wavenumber());
    Mat3 s = h_prev * pa * h_prev.transpose() + noise(z_prev).second;
    const double sign = meas.field.dot(s.inverse() * z_prev) >= 0.0 ? 1.0 : -1.0;
    const Vec3 z = sign * meas.field;
    Jacobian<kDenseDim, 3> k = pa * h_prev.transpose() * s.inverse();
    DenseVec xa_prev = xa0;
    DenseVec xa = xa0 + k * (z - z_prev);
    xa.tail<kCalibrationDim>().setZero();  // considered: E stays at its prior mean
    for (std::uint32_t it = 0; it < cfg.iterated_update_max; ++it) {
      Jacobian<3, kDenseDim> h_i;
      const Vec3 z_i = dense_h(xa, h_i, cfg.wavenumber());
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
      xa.tail<kCalibrationDim>().setZero();
    }
    expect_component(f.components()[i], dense_compose(xa, pa - k * s * k.transpose()), 1e-8, i);
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

// sog.censored_axes_in_update: an axis below detection bounds the field there. A mixture pinned
// down near the transmitter predicts a strong field on every axis; a sample whose x axis agrees
// and whose y and z are reported below detection fits it when only the valid axis is asked (off,
// shipped), and fits no Gaussian when all three are (on).
TEST(SogFilterTest, AnAxisBelowDetectionBoundsTheFieldOnlyWhenAskedTo) {
  for (const bool censored : {false, true}) {
    SogConfig cfg;
    cfg.censored_axes_in_update = censored;
    AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 5);
    SogFilter f(cfg);
    f.process(sim.measure());
    for (int k = 0; k < 40 && sim.true_relative_position().head<2>().norm() > 3.0; ++k) {
      f.add_odometry(sim.walk(bearing_to_truth(sim), 1.0));
      f.process(sim.measure());
    }
    ASSERT_GE(f.estimate().status, EstimatorStatus::kConverged) << censored;
    f.add_odometry(sim.walk(bearing_to_truth(sim), 0.5));
    FieldMeasurement z = sim.measure();
    ASSERT_GT(z.field.tail<2>().cwiseAbs().minCoeff(), 100.0 * z.noise_stddev.maxCoeff()) << "y and z are strong";
    z.valid_axes = 0b001;
    const SogStepResult r = f.process(z);
    if (censored) {
      // Each axis's sigma is 5 % of |h| plus the floor: y and z at a good fraction of |h| are
      // several sigmas from 0, beyond any Gaussian's 3-axis gate.
      EXPECT_GT(r.min_nis, chi_square_quantile(0.9999, 3.0))
          << "y and z read as 0 where the mixture predicts them strong";
    } else {
      EXPECT_LT(r.min_nis, chi_square_quantile(0.9999, 1.0)) << "the valid x axis alone agrees";
    }
  }
}

}  // namespace
}  // namespace sarloc::avalanche
