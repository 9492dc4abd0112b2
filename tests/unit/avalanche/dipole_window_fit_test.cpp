// One dipole fitted to a window of samples at once (dipole_window_fit.hpp), and the reach of a
// SOG filter's window (SogFilter::window_reaches): how far from its estimate its latest samples
// alone allow the transmitter.
#include "sarloc/core/avalanche/dipole_window_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/receiver_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sog_scenarios.hpp"

namespace sarloc::avalanche {
namespace {

constexpr double kCarrierHz = 457000.0;

// Samples of a dipole at `p` with moment `m` on a 3 x 3 grid of antenna positions 1 m apart,
// each receiver turned its own way, every other sample read with the opposite sign (a receiver
// measures +-h), with `relative_noise` of white noise per axis.
std::vector<WindowSample> grid_samples(const Vec3& p, const Vec3& m, double relative_noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  const double k = carrier_wavenumber(kCarrierHz);
  std::vector<WindowSample> out;
  int i = 0;
  for (int x = -1; x <= 1; ++x) {
    for (int y = -1; y <= 1; ++y, ++i) {
      WindowSample s;
      s.antenna = Vec3(x, y, 0.0);
      s.rotation = rotation_from_rpy(Vec3(0.05 * x, -0.04 * y, 0.7 * i));
      const Vec3 h = s.rotation.transpose() * DipoleField::major_axis(s.antenna - p, m, k);
      s.field = (i % 2 == 0 ? 1.0 : -1.0) * h;
      for (int a = 0; a < 3; ++a) s.field[a] += relative_noise * h.norm() * n(rng);
      s.floor = Vec3::Constant(2.1e-9);
      out.push_back(s);
    }
  }
  return out;
}

DipoleFitModel model() {
  DipoleFitModel m;
  m.wavenumber = carrier_wavenumber(kCarrierHz);
  return m;
}

TEST(DipoleWindowFit, RecoversTheDipoleFromNoiseFreeSamplesOfEitherSign) {
  const Vec3 p(0.5, -0.3, -2.5);
  const Vec3 m(0.008, -0.004, 0.01);
  const auto samples = grid_samples(p, m, 0.0, 1);
  const DipoleWindowFit fit(model(), samples, p);
  const auto best = fit.fit(p + Vec3(0.8, -0.6, 0.5), 0.5 * m);
  ASSERT_TRUE(best.has_value());
  EXPECT_LT((best->position - p).norm(), 1e-3);
  EXPECT_LT((best->moment - m).norm(), 1e-3 * m.norm());
  EXPECT_EQ(best->valid_axes, 27);
  // Held at the truth, only the moment is fitted: the same moment.
  const auto held = fit.fit_moment(p, 2.0 * m);
  ASSERT_TRUE(held.has_value());
  EXPECT_EQ(held->position, p);
  EXPECT_LT((held->moment - m).norm(), 1e-3 * m.norm());
}

TEST(DipoleWindowFit, TheTruthIsWithinTheLikelihoodRatioOfTheBestOverNoisyWindows) {
  // 200 windows at the filter's own noise (5 % per axis): -2 log of the likelihood ratio of the
  // truth against the best fit is chi-square with 6 degrees of freedom, so about 1 in 1000 is
  // above its 0.999 quantile. A fit stuck in a wrong minimum, or a deviance that is not the
  // noise model's, puts far more above it.
  const Vec3 p(-0.4, 0.6, -2.0);
  const Vec3 m(-0.006, 0.009, 0.007);
  const double gate = chi_square_quantile(0.999, 6.0);
  int above = 0;
  double mean_ratio = 0.0;
  constexpr int kWindows = 200;
  for (int w = 0; w < kWindows; ++w) {
    const DipoleWindowFit fit(model(), grid_samples(p, m, 0.05, 100 + w), p);
    const auto best = fit.fit(p + Vec3(0.3, 0.3, -0.3), m);
    const auto truth = fit.deviance(p, m);
    ASSERT_TRUE(best && truth);
    const double ratio = *truth - best->deviance;
    EXPECT_GE(ratio, -1e-6) << "window " << w << ": the fit is not the minimum";
    mean_ratio += ratio / kWindows;
    above += ratio > gate ? 1 : 0;
  }
  EXPECT_LE(above, 3);
  EXPECT_NEAR(mean_ratio, 6.0, 2.0);  // the chi-square's mean, within what 200 windows scatter
}

TEST(DipoleWindowFit, AWindowOnTheDipoleIsRefused) {
  std::vector<WindowSample> samples(12);
  for (auto& s : samples) s.field = Vec3(1e-6, 0.0, 2e-6);
  const DipoleWindowFit on_it(model(), samples, Vec3::Zero());
  EXPECT_FALSE(on_it.fit(Vec3::Zero(), Vec3(0.0, 0.0, 0.01)).has_value());  // every antenna on it
  for (auto& s : samples) s.axes = 0;
  const DipoleWindowFit unheard(model(), samples, Vec3::Zero());
  EXPECT_FALSE(unheard.deviance(Vec3(0.0, 0.0, -2.0), Vec3(0.0, 0.0, 0.01)).has_value());  // nothing heard
}

// A SOG filter walked onto a victim `depth_m` deep, then sampling either from one spot over it
// (moving 0.1 m) or around it 1.5 m out.
SogFilter walked_filter(double depth_m, bool around, std::uint32_t window, double* error) {
  Scenario s;
  s.transmitter = Vec3(6.0, 4.0, -depth_m);
  s.moment = Vec3(0.009, -0.004, 0.008);
  s.receiver = Vec3(0.0, 0.0, 1.0);
  s.receiver_rpy = Vec3(0.0, 0.0, 0.4);
  AvalancheSimulator sim(SimulationConfig{}, s, 7);
  SogConfig cfg;
  cfg.window_fit_samples = window;
  SogFilter f(cfg);
  f.process(sim.measure());
  for (int k = 0; k < 10; ++k) {
    f.add_odometry(sim.walk(test::bearing_to_truth(sim), std::min(1.0, sim.true_horizontal_distance())));
    f.process(sim.measure());
  }
  const Vec3 over = s.transmitter;
  for (int k = 0; k < 24; ++k) {
    const Vec3 to = around ? over + 1.5 * Vec3(std::cos(k * kPi / 6.0), std::sin(k * kPi / 6.0), 0.0)
                           : over + 0.1 * Vec3(k % 2 == 0 ? 1.0 : -1.0, 0.0, 0.0);
    const Vec3 rel = to - sim.scenario().receiver;
    f.add_odometry(
        sim.walk(std::atan2(rel.y(), rel.x()) - sim.scenario().receiver_rpy.z(), std::min(1.0, rel.head<2>().norm())));
    f.process(sim.measure());
  }
  *error = (f.estimate(0).relative.position - sim.true_relative_position()).norm();
  return f;
}

TEST(SogWindowReach, SamplesFromOneSpotOverADeepVictimAllowItFartherThanSamplesAroundIt) {
  // From one spot, depth and horizontal offset trade against the moment: the window pins the
  // victim down far less than a ring of samples around it does. 0.8 m: twice the located radius
  // of a victim under 4 m from the antenna (SearchConfig::confirm_window_reach_factor).
  double error = 0.0;
  const SogFilter ring = walked_filter(2.8, true, 24, &error);
  EXPECT_LT(error, 0.4);
  EXPECT_FALSE(ring.window_reaches(0.8));  // so a dipole was fitted to this geometry
  EXPECT_TRUE(ring.window_reaches(0.05));  // no window pins a victim 3.8 m away to 5 cm
  const SogFilter spot = walked_filter(2.8, false, 24, &error);
  EXPECT_TRUE(spot.window_reaches(0.8));
  const SogFilter off = walked_filter(2.8, false, 0, &error);
  EXPECT_FALSE(off.window_reaches(0.05));  // no window kept: it says nothing
}

}  // namespace
}  // namespace sarloc::avalanche
