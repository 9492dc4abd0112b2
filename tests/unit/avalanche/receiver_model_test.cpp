// The realistic receiver's field and axes (issue 12): the full dipole field, the reported major
// axis, the minor-axis bound, and the receiver's timing config.
#include "sarloc/core/avalanche/receiver_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/transmitter_standard.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {

TEST(FullDipoleField, QuasiStaticLimitIsTheSeedModel) {
  const Vec3 r(12.0, -5.0, 3.0), m(0.01, 0.004, -0.02);
  const Vec3c h = full_dipole_field(r, m, 0.0);
  const Vec3 quasi = DipoleField::field(r, m);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(h[i].real(), quasi[i], 1e-15);
    EXPECT_NEAR(h[i].imag(), 0.0, 1e-18);
  }
}

TEST(FullDipoleField, InductionTermAtFiftyMetres) {
  // On the dipole's axis only the radial part: 2 m (1/r^3 + j k/r^2) / (4 pi), |.| grows by
  // |1 + j k r| and is a quarter period out of phase for the 1/r^2 term.
  ReceiverModelConfig config;
  const double k = wavenumber(config);
  EXPECT_NEAR(k * 50.0, 0.479, 0.001);
  const Vec3 m(0.0, 0.0, 0.02);
  const Vec3c h = full_dipole_field(Vec3(0.0, 0.0, 50.0), m, k);
  const double quasi = DipoleField::field(Vec3(0.0, 0.0, 50.0), m).z();
  EXPECT_NEAR(std::abs(h.z()) / quasi, std::hypot(1.0, k * 50.0), 1e-9);
  EXPECT_NEAR(std::arg(h.z()), std::atan(k * 50.0), 1e-9);
}

TEST(PrincipalAxis, RecoversTheVectorUpToItsSign) {
  const Vec3 v(3e-8, -1e-8, 2e-8);
  for (double phi : {0.0, 0.4, 1.6, 2.9, -2.2}) {
    const Vec3c a = v.cast<std::complex<double>>() * std::polar(1.0, phi);
    const Vec3 p = principal_axis(a);
    EXPECT_NEAR(std::fabs(p.dot(v)) / v.squaredNorm(), 1.0, 1e-12) << "phi " << phi;
  }
}

TEST(MinorAxis, OneTransmitterIsLinearTwoSummedAreNot) {
  const Vec3 m(0.02, -0.01, 0.015);
  const double k = wavenumber(ReceiverModelConfig{});
  // One transmitter: linear to within (kr)^3 (the radiation term alone points elsewhere).
  for (double r : {2.0, 20.0, 50.0}) {
    const Vec3c h = full_dipole_field(Vec3(r * 0.6, r * 0.8, -1.0), m, k) * std::polar(1.0, 0.7);
    EXPECT_LT(minor_axis(h).norm(), (r < 30.0 ? 0.01 : 0.1) * principal_axis(h).norm()) << "r = " << r;
  }
  // Two of similar strength, their carrier phases a quarter cycle apart: clearly elliptical.
  const Vec3c a = full_dipole_field(Vec3(3.0, 1.0, -1.5), m, k);
  const Vec3c b = full_dipole_field(Vec3(2.0, -2.0, -1.0), Vec3(-0.01, 0.02, 0.0), k);
  const Vec3c sum = a + b * std::complex<double>(0.0, 1.0);
  EXPECT_GT(minor_axis(sum).norm(), 0.3 * principal_axis(sum).norm());
}

// The polarisation bound the separation applies (single_transmitter_ellipticity) holds for every
// transmitter of the standard, any orientation, 1-80 m, judged from the field it produces; and it
// is tight where it matters: below 0.01 at 20 m, near 0.1 at 60 m.
TEST(MinorAxis, SingleTransmitterBoundHoldsForEveryTransmitterOfTheStandard) {
  const double k = wavenumber(ReceiverModelConfig{});
  const TransmitterStandard standard;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double tightest = 1.0;
  for (int i = 0; i < 4000; ++i) {
    const double r = 1.0 + 79.0 * 0.5 * (u(rng) + 1.0);
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const double magnitude = standard.moment_min() + (standard.moment_max() - standard.moment_min()) * 0.5 * (u(rng) + 1.0);
    const Vec3 m = magnitude * Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3c h = full_dipole_field(r * dir, m, k) * std::polar(1.0, 3.0 * u(rng));
    const double major = principal_axis(h).norm();
    const double bound = single_transmitter_ellipticity(major, k, standard.moment_max());
    ASSERT_LE(minor_axis(h).norm(), bound * major) << "r " << r;
    tightest = std::min(tightest, bound * major / std::max(minor_axis(h).norm(), 1e-300));
  }
  const double at20 = single_transmitter_ellipticity(standard.strongest_on_axis_field(20.0), k, standard.moment_max());
  const double at60 = single_transmitter_ellipticity(standard.strongest_on_axis_field(60.0), k, standard.moment_max());
  EXPECT_LT(at20, 0.01);
  EXPECT_GT(at60, 0.08);
  EXPECT_LT(at60, 0.15);
  EXPECT_EQ(single_transmitter_ellipticity(0.0, k, standard.moment_max()), 1.0);
}

TEST(ReceiverModelConfig, RefusesTimingOutsideTheStandard) {
  ReceiverModelConfig c;
  c.period_min_ms = 600.0;
  EXPECT_THROW(c.validate(), ConfigError);
  c = ReceiverModelConfig{};
  c.on_time_min_ms = 50.0;
  EXPECT_THROW(c.validate(), ConfigError);
  c = ReceiverModelConfig{};
  c.carrier_tolerance_hz = 100.0;
  EXPECT_THROW(c.validate(), ConfigError);
}

}  // namespace
}  // namespace sarloc::avalanche
