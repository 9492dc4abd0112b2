// The receiver's calibration errors, fixed per device, carried as consider parameters
// (SogConfig::calibration_gain_sigma): a Monte Carlo NEES over devices drawn from the stated
// tolerance. The update's algebra is checked against the dense algorithm in sog_update_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/position_nees.hpp"
#include "sog_scenarios.hpp"

namespace sarloc::avalanche {
namespace {

constexpr double kGainSigma = 0.05;
constexpr double kPointingSigmaDeg = 3.0;

// A device's calibration errors drawn from the tolerance above: z = (I + E) h.
Mat3 draw_calibration(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Mat3 e;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) e(a, b) = n(rng) * (a == b ? kGainSigma : kPointingSigmaDeg * kDeg);
  return Mat3::Identity() + e;
}

// Mean NEES of the position after a rescuer's walk onto a victim 1 m deep and around it 1.5 m
// out, over `runs` devices each with its own calibration errors.
double mean_nees_over_devices(const SogConfig& cfg, int runs) {
  double sum = 0.0;
  for (int run = 0; run < runs; ++run) {
    std::mt19937_64 rng(300 + run);
    const Scenario s = test::random_victim_nearby(rng, 6.0, 1.0, cfg.standard.moment_min(), cfg.standard.moment_max());
    const Mat3 device = draw_calibration(rng);
    AvalancheSimulator sim(SimulationConfig{}, s, 500 + run);
    auto measure = [&] {
      FieldMeasurement m = sim.measure();
      m.field = device * m.field;
      return m;
    };
    SogFilter f(cfg);
    f.process(measure());
    test::walk_onto_and_around(sim, s.transmitter, 7, [&](const Odometry& odometry) {
      f.add_odometry(odometry);
      f.process(measure());
    });
    const VictimEstimate e = f.estimate();
    sum += position_nees(e.relative.position - sim.true_relative_position(), e.relative.covariance);
  }
  return sum / runs;
}

TEST(SogCalibrationTest, DevicesWithFixedErrorsStayConsistentWhenTheErrorsAreConsidered) {
  constexpr int kRuns = 16;
  const double lower = chi_square_quantile(0.025, 3 * kRuns) / kRuns;
  const double upper = chi_square_quantile(0.975, 3 * kRuns) / kRuns;
  SogConfig cfg;
  cfg.initial_components = 900;  // keep the unit test fast
  cfg.field_carrier_hz = 0.0;    // the simulator's ideal samples: the quasi-static field
  cfg.calibration_gain_sigma = kGainSigma;
  cfg.calibration_pointing_sigma_deg = kPointingSigmaDeg;
  const double considered = mean_nees_over_devices(cfg, kRuns);
  cfg.calibration_gain_sigma = 0.0;
  cfg.calibration_pointing_sigma_deg = 0.0;
  const double ignored = mean_nees_over_devices(cfg, kRuns);
  EXPECT_LT(considered, upper) << "ignored: " << ignored;
  EXPECT_GT(considered, lower);
  // Ignored, the same errors make the filter over-confident: the check above has something to catch.
  EXPECT_GT(ignored, upper) << "considered: " << considered;
}

// Only the moment, derived from the first sample, shares its calibration error when the mixture
// is built; a filter told of no calibration error keeps none.
TEST(SogCalibrationTest, TheFirstSampleTiesOnlyTheMomentToTheCalibration) {
  AvalancheSimulator sim(SimulationConfig{}, test::fixed_scenario(), 1);
  const FieldMeasurement first = sim.measure();
  SogConfig cfg;
  cfg.initial_components = 200;
  SogFilter on(cfg);
  on.process(first);
  for (const SogComponent& c : on.components()) {
    EXPECT_EQ(c.calibration_cross.topRows<6>().cwiseAbs().maxCoeff(), 0.0);
    EXPECT_GT(c.calibration_cross.bottomRows<3>().cwiseAbs().maxCoeff(), 0.0);
  }
  cfg.calibration_gain_sigma = 0.0;
  cfg.calibration_pointing_sigma_deg = 0.0;
  SogFilter off(cfg);
  off.process(first);
  for (const SogComponent& c : off.components()) EXPECT_EQ(c.calibration_cross.cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace sarloc::avalanche
