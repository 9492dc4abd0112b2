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

namespace sarloc::avalanche {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Scenario fixed_scenario() {
  Scenario s;
  s.transmitter = Vec3(30.0, 20.0, -1.5);
  s.moment = Vec3(0.01, -0.005, 0.012);
  s.receiver = Vec3(0.0, 0.0, 1.0);
  s.receiver_rpy = Vec3(0.02, -0.03, 0.7);
  return s;
}

// fixed_scenario()'s walk with another transmitter 2 m from its one, with another moment.
Scenario second_transmitter() {
  Scenario b = fixed_scenario();
  b.transmitter += Vec3(-1.0, 1.5, -1.0);
  b.moment = Vec3(-0.004, 0.012, 0.006);
  return b;
}

// Receiver-frame bearing that walks the simulated rescuer straight at the transmitter.
double bearing_to_truth(const AvalancheSimulator& sim) {
  const Vec3 rel = sim.true_relative_position();
  return std::atan2(rel.y(), rel.x()) - sim.scenario().receiver_rpy.z();
}

TEST(SogConfigTest, DefaultsValidAndMessagesNameKeyAndValue) {
  EXPECT_NO_THROW(SogConfig{}.validate());
  SogConfig c;
  c.initial_components = 0;
  try {
    c.validate();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "sog.initial_components = 0: must be > 0");
  }
  SogConfig d;
  d.noise_floor_A_per_m = kNaN;
  EXPECT_THROW(d.validate(), ConfigError);
  SogConfig e;
  e.standard.field_max_A_per_m = 1e-9;  // below field_min
  EXPECT_THROW(e.validate(), ConfigError);
  EXPECT_THROW(SogFilter{d}, ConfigError);
}

TEST(SogFilterTest, InitialisesRingAroundTruthWithMomentBounds) {
  SimulationConfig sc;
  AvalancheSimulator sim(sc, fixed_scenario(), 3);
  SogConfig cfg;
  SogFilter f(cfg);
  EXPECT_FALSE(f.initialised());
  EXPECT_EQ(f.estimate().status, EstimatorStatus::kInitialising);
  const auto r = f.process(sim.measure());
  EXPECT_TRUE(r.initialised_now);
  // About 1700 components (the spacing is adapted to the accepted count).
  EXPECT_NEAR(static_cast<double>(f.size()), 1700.0, 100.0);
  const double d_true = sim.true_relative_position().head<2>().norm();
  double rho_min = 1e9, rho_max = 0.0, wsum = 0.0;
  for (const auto& c : f.components()) {
    const double rho = c.x.segment<2>(idx::kPos).norm();
    rho_min = std::min(rho_min, rho);
    rho_max = std::max(rho_max, rho);
    const double m = c.x.segment<3>(idx::kMom).norm();
    EXPECT_GE(m, cfg.standard.moment_min() * (1 - cfg.moment_margin) - 1e-12);
    EXPECT_LE(m, cfg.standard.moment_max() * (1 + cfg.moment_margin) + 1e-12);
    EXPECT_TRUE(c.P.allFinite());
    EXPECT_GT(c.P.diagonal().minCoeff(), 0.0);
    wsum += std::exp(c.log_weight);
  }
  EXPECT_NEAR(wsum, 1.0, 1e-9);
  EXPECT_LT(rho_min, d_true);
  EXPECT_GT(rho_max, d_true);
}

TEST(SogFilterTest, ConvergesOnTruthWhileWalkingTowardsIt) {
  // A straight walk towards the transmitter (no controller): the filter alone must localise.
  SimulationConfig sc;
  AvalancheSimulator sim(sc, fixed_scenario(), 11);
  SogConfig cfg;
  cfg.initial_components = 600;  // keep the unit test fast
  SogFilter f(cfg);
  f.process(sim.measure());
  for (int k = 0; k < 33; ++k) {
    f.add_odometry(sim.walk(bearing_to_truth(sim), 1.0));
    f.process(sim.measure());
  }
  const VictimEstimate e = f.estimate(3);
  const Vec3 err = e.relative.position - sim.true_relative_position();
  EXPECT_LT(err.norm(), 0.5) << "estimate " << e.relative.position.transpose() << " truth "
                             << sim.true_relative_position().transpose();
  EXPECT_EQ(e.status, EstimatorStatus::kConverged);
  EXPECT_LT(f.size(), 100u);
  ASSERT_FALSE(e.top_components.empty());
  EXPECT_GE(e.top_components.front().weight, e.top_components.back().weight);
  // The error is consistent with the reported covariance (generous: one trial, 3 dof).
  EXPECT_LT(err.dot(e.relative.covariance.ldlt().solve(err)), 16.0);
}

// The NEES of a filter first heard a few metres from a victim 4 m deep, after the walk a
// rescuer makes there (onto it, then around it 1.5 m out), over runs with random azimuths,
// moments and noise: the filter's mixture of depth layers must cover that victim with
// Gaussians narrow enough for 1/r^3 to be near linear over each.
double mean_nees_near_a_deep_victim(const SogConfig& cfg, int runs) {
  double sum = 0.0;
  for (int run = 0; run < runs; ++run) {
    std::mt19937_64 rng(700 + run);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double az = 2.0 * kPi * u(rng);
    Scenario s;
    s.transmitter = Vec3(4.5 * std::cos(az), 4.5 * std::sin(az), -4.0);
    const Vec3 dir = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
    s.moment = dir * (cfg.standard.moment_min() + u(rng) * (cfg.standard.moment_max() - cfg.standard.moment_min()));
    s.receiver = Vec3(0.0, 0.0, 1.0);
    s.receiver_rpy = Vec3(0.0, 0.0, 2.0 * kPi * u(rng));
    AvalancheSimulator sim(SimulationConfig{}, s, 900 + run);
    SogFilter f(cfg);
    f.process(sim.measure());
    auto walk_to = [&](const Vec3& point) {
      const Vec3 rel = point - sim.scenario().receiver;
      const double step = std::min(1.0, rel.head<2>().norm());
      f.add_odometry(sim.walk(std::atan2(rel.y(), rel.x()) - sim.scenario().receiver_rpy.z(), step));
      f.process(sim.measure());
    };
    for (int k = 0; k < 6; ++k) walk_to(s.transmitter);
    for (int k = 0; k < 12; ++k)
      walk_to(s.transmitter + 1.5 * Vec3(std::cos(k * kPi / 3.0), std::sin(k * kPi / 3.0), 0.0));
    const VictimEstimate e = f.estimate();
    const Vec3 err = e.relative.position - sim.true_relative_position();
    sum += err.dot(e.relative.covariance.ldlt().solve(err));
  }
  return sum / runs;
}

TEST(SogFilterTest, FirstHeardNearADeepVictimTheCovarianceHoldsTheTruth) {
  constexpr int kRuns = 12;
  const double upper = chi_square_quantile(0.975, 3 * kRuns) / kRuns;
  SogConfig cfg;
  cfg.initial_components = 900;  // keep the unit test fast
  EXPECT_LT(mean_nees_near_a_deep_victim(cfg, kRuns), upper);
  // One 0-3 m layer at every range, as before the near-field layers: overconfident there.
  cfg.near_field_depth_sigma_per_range = 0.0;
  EXPECT_GT(mean_nees_near_a_deep_victim(cfg, kRuns), upper);
}

TEST(SogFilterTest, ZeroDisplacementWithoutOdometryKeepsBelief) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 5);
  SogConfig cfg;
  cfg.initial_components = 200;
  SogFilter f(cfg);
  f.process(sim.measure());
  const Vec3 before = f.estimate().relative.position;
  f.process(sim.measure());  // no odometry in between: idle displacement
  EXPECT_LT((f.estimate().relative.position - before).norm(), 15.0);
  EXPECT_EQ(f.steps(), 2u);
}

TEST(SogFilterTest, RejectsBadMeasurementsNamingTheField) {
  SogConfig cfg;
  cfg.initial_components = 100;
  SogFilter f(cfg);
  FieldMeasurement m;
  m.sequence = 1;
  m.field = Vec3(1e-7, kNaN, 0);
  try {
    f.process(m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field_measurement.field"), std::string::npos);
  }
  m.field = Vec3(100.0, 0, 0);
  EXPECT_THROW(f.process(m), InputError);  // absurd magnitude
  m.field = Vec3::Zero();
  EXPECT_THROW(f.process(m), InputError);  // cannot initialise from zero
  m.field = Vec3(1e-7, 2e-8, -3e-8);
  m.orientation = OrientationObservation{};
  m.orientation->covariance = -Mat3::Identity();
  EXPECT_THROW(f.process(m), InputError);  // non-PD covariance
  m.orientation.reset();
  m.noise_stddev = Vec3(-1, 0, 0);
  EXPECT_THROW(f.process(m), InputError);
  m.noise_stddev = Vec3::Zero();
  f.process(m);
  EXPECT_THROW(f.process(m), InputError);  // same sequence again
  Odometry o;
  o.sequence = 1;
  o.covariance = Mat6::Identity() * 1e-4;
  o.translation = Vec3(kNaN, 0, 0);
  EXPECT_THROW(f.add_odometry(o), InputError);
  o.translation = Vec3(1, 0, 0);
  o.covariance(0, 0) = -1.0;
  EXPECT_THROW(f.add_odometry(o), InputError);
}

TEST(OdometryAccumulatorTest, ComposesSamplesAndPropagatesCovariance) {
  OdometryAccumulator acc;
  Odometry a;
  a.sequence = 1;
  a.translation = Vec3(1, 0, 0);
  a.rotation_rpy = Vec3(0, 0, kPi / 2);
  a.covariance = Mat6::Identity() * 1e-4;
  Odometry b = a;
  b.sequence = 2;
  acc.add(a);
  acc.add(b);
  const Displacement d = acc.take();
  EXPECT_EQ(d.samples, 2u);
  EXPECT_LT((d.mean.head<3>() - Vec3(1, 1, 0)).norm(), 1e-12);
  EXPECT_NEAR(d.mean[5], kPi, 1e-12);
  // Two steps: more uncertain than one, and the yaw uncertainty leaks into translation.
  EXPECT_GT(d.covariance(1, 1), 1e-4);
  const Displacement idle = acc.take();
  EXPECT_EQ(idle.samples, 0u);
  EXPECT_TRUE(idle.mean.isZero());
  EXPECT_GT(idle.covariance.diagonal().minCoeff(), 0.0);
  Odometry old = a;  // sequence 1 again: out of order
  EXPECT_THROW(acc.add(old), InputError);
}

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

// Surface term (SogConfig::surface_constraint): after every step, including the components a
// merge produced, each component's log_support is log P(p_z below the surface) of its own
// Gaussian (one implementation, SogFilter::prior_log_support).
TEST(SogFilterTest, SurfaceSupportIsThatOfEachComponentAfterMerging) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 13);
  SogConfig cfg;
  cfg.initial_components = 400;
  cfg.surface_constraint = true;
  cfg.moment_constraint = false;
  cfg.merge_cell_m = 10.0;  // merge often
  cfg.merge_mahalanobis = 50.0;
  SogFilter f(cfg);
  f.process(sim.measure());
  std::size_t merged = 0;
  for (int k = 0; k < 8; ++k) {
    f.add_odometry(sim.walk(bearing_to_truth(sim), 1.0));
    merged += f.process(sim.measure()).merged;
    for (const SogComponent& c : f.components()) {
      const double u = (-cfg.antenna_height_m - c.x[idx::kPos + 2]) /
                       std::sqrt(c.P(idx::kPos + 2, idx::kPos + 2));
      ASSERT_NEAR(c.log_support, log_normal_cdf(u), 1e-12);
    }
  }
  EXPECT_GT(merged, 0u);
}

// Moment term (SogConfig::moment_constraint): each component's log_support (folded into its
// weight) is log P(|m| within the standard's bounds +- moment_margin) of its own Gaussian, |m|
// linearised along its mean, checked against the normal CDF difference directly; far outside it
// stays finite.
TEST(SogFilterTest, MomentSupportIsTheStandardsBoundsUnderEachGaussian) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 13);
  SogConfig cfg;
  cfg.initial_components = 400;
  cfg.moment_constraint = true;
  SogFilter f(cfg);
  f.process(sim.measure());
  const double lo = cfg.standard.moment_min() * (1.0 - cfg.moment_margin);
  const double hi = cfg.standard.moment_max() * (1.0 + cfg.moment_margin);
  auto phi = [](double u) { return 0.5 * std::erfc(-u / std::sqrt(2.0)); };
  std::size_t checked = 0;
  for (int k = 0; k < 6; ++k) {
    f.add_odometry(sim.walk(bearing_to_truth(sim), 1.0));
    f.process(sim.measure());
    for (const SogComponent& c : f.components()) {
      const Vec3 m = c.x.segment<3>(idx::kMom);
      const double sd = std::sqrt(m.normalized().dot(c.P.block<3, 3>(idx::kMom, idx::kMom) * m.normalized()));
      const double p = phi((hi - m.norm()) / sd) - phi((lo - m.norm()) / sd);
      ASSERT_TRUE(std::isfinite(c.log_support));
      if (p < 1e-300) {  // the direct difference underflows; the filter's tail form does not
        EXPECT_LT(c.log_support, -690.0);
        continue;
      }
      ASSERT_NEAR(c.log_support, std::log(p), 1e-9);
      ++checked;
    }
  }
  EXPECT_GT(checked, 100u);
}

TEST(SogFilterTest, CopiesAreIndependent) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 9);
  SogConfig cfg;
  cfg.initial_components = 150;
  SogFilter a(cfg);
  a.process(sim.measure());
  SogFilter b = a;
  a.add_odometry(sim.walk(0.0, 1.0));
  a.process(sim.measure());
  EXPECT_EQ(b.steps(), 1u);
  EXPECT_EQ(a.steps(), 2u);
}

}  // namespace
}  // namespace sarloc::avalanche

namespace sarloc::avalanche {
namespace {

// Divergence recovery (SogConfig::divergence_window): the mixture is built from a first reading
// of a distant, weak decoy (ring 40-90 m), then fed readings of a strong transmitter 12 m away,
// outside every hypothesis, as when the true hypothesis was pruned at the noise floor. Without
// the windowed innovation test the filter never recovers; with it, it re-initialises from the
// current reading and localises the transmitter while the rescuer keeps walking.
double run_lost_filter(std::uint32_t window, int* reinitialisations) {
  SimulationConfig sc;
  Scenario decoy;
  decoy.transmitter = Vec3(-55.0, 10.0, -1.0);
  decoy.moment = Vec3(0.0, 0.0, 0.007);  // weakest moment, receiver in its equatorial plane
  decoy.receiver = Vec3(0.0, 0.0, 1.0);
  decoy.receiver_rpy = Vec3(0.0, 0.0, 0.3);
  Scenario truth = decoy;
  truth.transmitter = Vec3(10.0, 6.0, -1.5);
  truth.moment = Vec3(0.012, 0.01, 0.015);
  AvalancheSimulator first(sc, decoy, 5);
  AvalancheSimulator sim(sc, truth, 6);
  SogConfig cfg;
  cfg.initial_components = 600;  // keep the unit test fast
  cfg.divergence_window = window;
  SogFilter f(cfg);
  f.process(first.measure());
  sim.measure();  // same sequence number as the decoy reading
  *reinitialisations = 0;
  for (int k = 0; k < 14; ++k) {
    const double step = sim.true_relative_position().head<2>().norm() > 3.0 ? 1.0 : 0.3;
    f.add_odometry(sim.walk(bearing_to_truth(sim), step));
    if (f.process(sim.measure()).reinitialised) ++*reinitialisations;
  }
  return (f.estimate(0).relative.position - sim.true_relative_position()).norm();
}

TEST(SogFilterTest, WindowedInnovationTestRecoversALostMixture) {
  int reinit_off = 0, reinit_on = 0;
  const double err_off = run_lost_filter(0, &reinit_off);
  const double err_on = run_lost_filter(6, &reinit_on);
  EXPECT_EQ(reinit_off, 0);
  EXPECT_GT(err_off, 5.0) << "the lost mixture should not find the transmitter by itself";
  EXPECT_GE(reinit_on, 1);
  EXPECT_LT(err_on, 1.0);
}

// The walk of ConvergesOnTruthWhileWalkingTowardsIt (600 components, 33 straight steps at the
// transmitter), counting re-initialisations on the way.
SogFilter walk_to_fixed_transmitter(AvalancheSimulator& sim, int* reinitialisations,
                                    double leap_gate_probability = SogConfig{}.leap_gate_probability,
                                    double converged_divergence_ratio = SogConfig{}.converged_divergence_ratio) {
  SogConfig cfg;
  cfg.initial_components = 600;
  cfg.leap_gate_probability = leap_gate_probability;
  cfg.converged_divergence_ratio = converged_divergence_ratio;
  SogFilter f(cfg);
  f.process(sim.measure());
  *reinitialisations = 0;
  for (int k = 0; k < 33; ++k) {
    f.add_odometry(sim.walk(bearing_to_truth(sim), 1.0));
    if (f.process(sim.measure()).reinitialised) ++*reinitialisations;
  }
  return f;
}

// The leap test (SogConfig::leap_gate_probability): a filter converged on one transmitter is
// then fed another's samples, as when its signal took the pulses of a victim 2 m away (multiple
// burials). Its mean drifts out of its own posterior while its radius shrinks; with the test it
// is rebuilt from the current sample and ends on the transmitter it now hears. Returns the
// final error from that one and its stated 95 % radius.
struct SwitchedRun {
  int leaps = 0;
  std::uint64_t mixture_samples_at_leap = 0;  ///< of the last leap, right after it
  std::uint64_t steps_at_leap = 0;
  double error_m = 0.0;
  double radius95_m = 0.0;
};

// converged_divergence_ratio 1e6: the divergence test spares every converged mixture, as it did
// when the leap test was introduced (the leap test's own effect).
SwitchedRun run_switched_signal(double leap_probability, double leap_min_range_m = SogConfig{}.leap_min_range_m,
                                double converged_divergence_ratio = 1e6) {
  AvalancheSimulator sim_a(SimulationConfig{}, fixed_scenario(), 21);
  AvalancheSimulator sim_b(SimulationConfig{}, second_transmitter(), 21);  // one walk, two fields
  SogConfig cfg;
  cfg.initial_components = 600;
  cfg.leap_gate_probability = leap_probability;
  cfg.leap_min_range_m = leap_min_range_m;
  cfg.converged_divergence_ratio = converged_divergence_ratio;
  SogFilter f(cfg);
  f.process(sim_a.measure());
  sim_b.measure();
  SwitchedRun run;
  bool heard_b = false;  // A's samples until 5 m from it, then B's, walking slowly towards B
  for (int k = 0; k < 70; ++k) {
    heard_b = heard_b || sim_a.true_horizontal_distance() < 5.0;
    AvalancheSimulator& target = heard_b ? sim_b : sim_a;
    const double step = heard_b ? (target.true_horizontal_distance() > 1.0 ? 0.2 : 0.05) : 1.0;
    const double bearing = bearing_to_truth(target);
    f.add_odometry(sim_a.walk(bearing, step));
    sim_b.walk(bearing, step);
    const FieldMeasurement za = sim_a.measure(), zb = sim_b.measure();
    if (f.process(heard_b ? zb : za).leapt) {
      ++run.leaps;
      run.mixture_samples_at_leap = f.mixture_samples();
      run.steps_at_leap = f.steps();
    }
  }
  EXPECT_LT((sim_a.scenario().receiver - sim_b.scenario().receiver).norm(), 1e-9) << "the two walks parted";
  const VictimEstimate e = f.estimate(0);
  run.error_m = (e.relative.position - sim_b.true_relative_position()).norm();
  run.radius95_m = radius95_3d(e.relative.covariance);
  return run;
}

TEST(SogFilterTest, LeapTestRebuildsAFilterThatTookAnotherTransmittersSamples) {
  const SwitchedRun on = run_switched_signal(0.999);
  EXPECT_GE(on.leaps, 1);
  // The rebuilt mixture is a new guess: its samples are counted again (confirm_min_samples).
  EXPECT_EQ(on.mixture_samples_at_leap, 1U);
  EXPECT_GT(on.steps_at_leap, 10U);
  EXPECT_LT(on.error_m, on.radius95_m + 0.2) << "ends on the transmitter it hears";
  const SwitchedRun off = run_switched_signal(0.0);
  EXPECT_EQ(off.leaps, 0);
  EXPECT_GT(off.error_m, off.radius95_m) << "without the test the estimate is a blend of the two";
  // Nothing is rebuilt nearer than leap_min_range_m (the near field): here, nowhere.
  EXPECT_EQ(run_switched_signal(0.999, 100.0).leaps, 0);
  // With the default converged_divergence_ratio the gross innovation excess of the other
  // transmitter's samples rebuilds the filter first, leap test or not.
  const SwitchedRun divergence_only = run_switched_signal(0.0, SogConfig{}.leap_min_range_m, SogConfig{}.converged_divergence_ratio);
  EXPECT_LT(divergence_only.error_m, divergence_only.radius95_m + 0.2);
  SogConfig bad;
  bad.leap_gate_probability = 0.3;
  EXPECT_THROW(bad.validate(), ConfigError);
  SogConfig bad_range;
  bad_range.leap_min_range_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(bad_range.validate(), ConfigError);
}

// A mixture converged where no buried transmitter can be (here above the receiver, as on a
// filter's mirror solution; or on a moment outside the standard) fits its data all the same:
// neither the divergence nor the leap test undoes it. After implausible_rebuild_steps converged
// updates it is rebuilt from the current sample; on the same walk to a buried transmitter it
// never is.
TEST(SogFilterTest, AMixtureConvergedWhereNoTransmitterCanBeIsRebuilt) {
  auto rebuilds = [](double transmitter_z, std::uint32_t after) {
    Scenario s = fixed_scenario();
    s.transmitter.z() = transmitter_z;
    AvalancheSimulator sim(SimulationConfig{}, s, 12);
    SogConfig cfg;
    cfg.initial_components = 600;
    cfg.implausible_rebuild_steps = after;
    SogFilter f(cfg);
    f.process(sim.measure());
    int n = 0;
    for (int k = 0; k < 70; ++k) {
      const double step = sim.true_horizontal_distance() > 1.0 ? 1.0 : 0.2;
      f.add_odometry(sim.walk(bearing_to_truth(sim), step));
      const SogStepResult r = f.process(sim.measure());
      if (r.rebuilt_implausible) {
        ++n;
        EXPECT_EQ(f.mixture_samples(), 1U);
      }
    }
    return n;
  };
  EXPECT_GE(rebuilds(2.5, 20), 1);
  EXPECT_EQ(rebuilds(2.5, 0), 0) << "0 = off";
  EXPECT_EQ(rebuilds(-1.5, 20), 0) << "a buried transmitter is never rebuilt";
  SogConfig bad;
  bad.implausible_rebuild_steps = 10001;
  EXPECT_THROW(bad.validate(), ConfigError);
}

// The confirmation's longer window is the divergence window's statistic over more samples: over
// exactly divergence_window samples the two agree; over more, the sum of the smallest NIS of
// that many updates (fewer while the mixture is younger) over its chi-square gate.
TEST(SogFilterTest, InnovationRatioOverAWindowIsTheDivergenceStatistic) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 11);
  int reinitialisations = -1;
  const SogFilter f = walk_to_fixed_transmitter(sim, &reinitialisations);
  ASSERT_EQ(reinitialisations, 0);
  const std::size_t window = f.config().divergence_window;
  EXPECT_NEAR(f.innovations().ratio_over(window), f.innovations().recent_ratio(), 1e-12);
  EXPECT_GT(f.innovations().ratio_over(18), 0.0);
  EXPECT_NEAR(f.innovations().ratio_over(1000), f.innovations().ratio_over(f.mixture_samples()), 1e-12);
  EXPECT_DOUBLE_EQ(SogFilter().innovations().ratio_over(18), 0.0);
}

// The confirmation's probe window: of the updates made while the 95 % radius was within a bound,
// the latest n, their smallest NIS summed with one degree of freedom per valid axis. Checked
// against the updates' own results while walking on, one sample in three with a single axis.
TEST(SogFilterTest, InnovationsWithinARadiusSumTheNisOfTheSamplesItPredictedClosely) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 11);
  int reinitialisations = -1;
  SogFilter f = walk_to_fixed_transmitter(sim, &reinitialisations);
  ASSERT_EQ(reinitialisations, 0);
  struct Update {
    double nis, dof, radius95_before;
  };
  std::vector<Update> updates;
  for (int k = 0; k < 12; ++k) {
    f.add_odometry(sim.walk(bearing_to_truth(sim) + 1.5, 0.5));
    FieldMeasurement z = sim.measure();
    z.sequence = 1000 + k;
    if (k % 3 == 0) z.valid_axes = 0b001;
    const double before = radius95_3d(f.estimate(0).relative.covariance);
    const SogStepResult r = f.process(z);
    ASSERT_FALSE(r.reinitialised);
    updates.push_back({r.min_nis, k % 3 == 0 ? 1.0 : 3.0, before});
  }
  const auto sum_of = [&](double max_radius, std::size_t n) {
    InnovationRecord::Sum s;
    for (auto it = updates.rbegin(); it != updates.rend() && n > 0; ++it) {
      if (it->radius95_before > max_radius) continue;
      s.nis += it->nis;
      s.dof += it->dof;
      --n;
    }
    return s;
  };
  for (const std::size_t n : {1u, 5u, 12u}) {
    const auto got = f.innovations().within(1e9, n);
    EXPECT_NEAR(got.nis, sum_of(1e9, n).nis, 1e-9) << n;
    EXPECT_DOUBLE_EQ(got.dof, sum_of(1e9, n).dof) << n;
  }
  std::vector<double> radii;
  for (const Update& u : updates) radii.push_back(u.radius95_before);
  std::sort(radii.begin(), radii.end());
  const double median = radii[radii.size() / 2];
  const auto some = f.innovations().within(median, 4);
  EXPECT_NEAR(some.nis, sum_of(median, 4).nis, 1e-9);
  EXPECT_DOUBLE_EQ(some.dof, sum_of(median, 4).dof);
  EXPECT_DOUBLE_EQ(f.innovations().within(0.0, 10).dof, 0.0) << "none was predicted that closely";
  EXPECT_DOUBLE_EQ(SogFilter().innovations().within(1e9, 10).dof, 0.0);
}

TEST(SogFilterTest, WindowedInnovationTestIsQuietOnAConsistentRun) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 11);
  int reinitialisations = -1;
  walk_to_fixed_transmitter(sim, &reinitialisations);
  EXPECT_EQ(reinitialisations, 0) << "no false re-initialisation";
  SogConfig bad;
  bad.divergence_window = 101;
  EXPECT_THROW(bad.validate(), ConfigError);
}

// A converged mixture is spared by the divergence test while its excess is moderate: there an
// innovation excess comes from linearising the dipole model next to the transmitter, and a ring
// rebuilt from a near-field reading lost victims already pinned down. Not once the window sum
// exceeds its gate converged_divergence_ratio times over: that is a lost transmitter. After
// converging on the walk above, the filter is fed readings of a transmitter 1.5 m away from the
// one it tracks. Sparing every converged mixture (the ratio 1e6), the test fails, is reported,
// and the mixture is kept; with the default, each step it spares is within the ratio, and the
// gross excess rebuilds it. (The leap test, off here, rebuilds such a filter from 3 m out, where
// its estimate leaves its own posterior: LeapTestRebuildsAFilterThatTookAnotherTransmittersSamples.)
TEST(SogFilterTest, DivergenceOfAConvergedMixtureIsReportedNotReinitialised) {
  for (const double ratio : {1e6, SogConfig{}.converged_divergence_ratio}) {
    SimulationConfig sc;
    AvalancheSimulator sim(sc, fixed_scenario(), 11);
    int reinitialisations = -1;
    SogFilter f = walk_to_fixed_transmitter(sim, &reinitialisations, 0.0, ratio);
    ASSERT_EQ(f.estimate(0).status, EstimatorStatus::kConverged);
    Scenario moved = sim.scenario();
    moved.transmitter += Vec3(1.0, -1.0, -0.5);
    AvalancheSimulator other(sc, moved, 12);
    int ignored = 0, rebuilt = 0;
    for (int k = 0; k < 10; ++k) {
      f.add_odometry(sim.walk(bearing_to_truth(sim), 0.5));
      other.walk(bearing_to_truth(other), 0.5);
      FieldMeasurement z = other.measure();
      z.sequence = 1000 + k;
      const SogStepResult r = f.process(z);
      if (r.reinitialised) ++rebuilt;
      if (r.divergence_ignored) {
        ++ignored;
        EXPECT_LE(f.innovations().recent_ratio(), ratio) << "step " << k;
      }
    }
    if (ratio > 1e5) {
      EXPECT_EQ(rebuilt, 0);
      EXPECT_GE(ignored, 1) << "the innovation test should have failed on these readings";
      EXPECT_EQ(f.estimate(0).status, EstimatorStatus::kConverged);
      // What the search controller refuses to confirm: the recent samples do not fit the filter.
      EXPECT_GT(f.innovations().recent_ratio(), 1.0);
    } else {
      EXPECT_GE(rebuilt, 1) << "a gross excess is a lost transmitter";
    }
  }
  SogConfig bad;
  bad.converged_divergence_ratio = 0.5;
  EXPECT_THROW(bad.validate(), ConfigError);
}

TEST(SogFilterTest, RecentInnovationsOfAConsistentRunAreWithinTheGate) {
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 11);
  int reinitialisations = -1;
  const SogFilter f = walk_to_fixed_transmitter(sim, &reinitialisations);
  EXPECT_GT(f.innovations().recent_ratio(), 0.0) << "the window is full after a walk";
  EXPECT_LE(f.innovations().recent_ratio(), 1.0);
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

// A transmitter the standard does not allow (10x its largest moment) is estimated as one, and
// the filter says so; a compliant one is plausible.
TEST(SogFilterTest, MomentOutsideTheStandardIsImplausible) {
  for (const double scale : {1.0, 10.0}) {
    Scenario s = fixed_scenario();
    s.moment *= scale;
    AvalancheSimulator sim(SimulationConfig{}, s, 9);
    SogFilter f;
    for (int k = 0; k < 45 && sim.true_horizontal_distance() > 1.0; ++k) {
      f.process(sim.measure());
      f.add_odometry(sim.walk(bearing_to_truth(sim), 1.0));
    }
    f.process(sim.measure());
    EXPECT_EQ(f.moment_plausible(), scale == 1.0) << "moment x" << scale << ", |m| estimated "
                                                  << f.moments().mean.segment<3>(idx::kMom).norm();
  }
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

namespace sarloc::avalanche {
namespace {

// Evidence that conflicts (RescuerSearch's found witness): two filters of one signal, given the
// same odometry, converged 2 m apart, one on the transmitter heard (A), one on another (B). Each
// takes half of the joined mixture, and A's samples that follow decide for A, whichever filter
// the other's hypotheses were added to.
TEST(SogFilterTest, AddedHypothesesKeepHalfTheMassAndTheSamplesToComeDecide) {
  for (const bool into_right : {true, false}) {
    AvalancheSimulator sim_a(SimulationConfig{}, fixed_scenario(), 21);
    AvalancheSimulator sim_b(SimulationConfig{}, second_transmitter(), 21);  // one walk, two fields
    SogConfig cfg;
    cfg.initial_components = 600;
    SogFilter right(cfg), wrong(cfg);
    right.process(sim_a.measure());
    wrong.process(sim_b.measure());
    for (int k = 0; k < 40; ++k) {
      const double step = sim_a.true_horizontal_distance() > 2.0 ? 1.0 : 0.3;
      const Odometry o = sim_a.walk(bearing_to_truth(sim_a), step);
      sim_b.walk(bearing_to_truth(sim_a), step);
      right.add_odometry(o);
      wrong.add_odometry(o);
      right.process(sim_a.measure());
      wrong.process(sim_b.measure());
    }
    const Vec3 truth = sim_a.true_relative_position();
    ASSERT_LT((right.estimate(0).relative.position - truth).norm(), 0.5);
    ASSERT_GT((wrong.estimate(0).relative.position - truth).norm(), 1.0) << "the other filter converged elsewhere";
    SogFilter joined = into_right ? right : wrong;
    const SogFilter& added = into_right ? wrong : right;
    ASSERT_TRUE(joined.add_hypotheses(added));
    EXPECT_EQ(joined.size(), right.size() + wrong.size());
    double mass = 0.0, of_added = 0.0;
    for (std::size_t i = 0; i < joined.size(); ++i) {
      const double w = std::exp(joined.components()[i].log_weight);
      mass += w;
      if (i >= joined.size() - added.size()) of_added += w;
    }
    EXPECT_NEAR(mass, 1.0, 1e-9);
    EXPECT_NEAR(of_added, 0.5, 1e-9);
    EXPECT_GT(radius95_3d(joined.estimate(0).relative.covariance), 1.0) << "two places, not one";
    // A's samples from around it decide.
    for (int k = 0; k < 12; ++k) {
      const Odometry o = sim_a.walk(bearing_to_truth(sim_a) + 2.0 * k, 0.5);
      joined.add_odometry(o);
      joined.process(sim_a.measure());
    }
    const VictimEstimate e = joined.estimate(0);
    EXPECT_LT((e.relative.position - sim_a.true_relative_position()).norm(), 0.5) << "joined into the right one: " << into_right;
    EXPECT_LT(radius95_3d(e.relative.covariance), 1.0);
  }
  // Only filters of one frame join: another stamp is refused, and so is an empty filter.
  SogFilter one, other, empty;
  AvalancheSimulator sim(SimulationConfig{}, fixed_scenario(), 3);
  one.process(sim.measure());
  sim.walk(0.0, 1.0);
  other.process(sim.measure());
  EXPECT_FALSE(one.add_hypotheses(other));
  EXPECT_FALSE(one.add_hypotheses(empty));
  EXPECT_FALSE(empty.add_hypotheses(one));
}

}  // namespace
}  // namespace sarloc::avalanche
