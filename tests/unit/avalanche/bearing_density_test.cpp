#include "sarloc/core/avalanche/bearing_density.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"

namespace sarloc::avalanche {
namespace {

constexpr double kDeg = kPi / 180.0;

TransmitterHypothesis at_bearing(double bearing_deg, double range_m, double weight) {
  TransmitterHypothesis c;
  c.position = Vec3(range_m * std::cos(bearing_deg * kDeg), range_m * std::sin(bearing_deg * kDeg), -2.0);
  c.weight = weight;
  return c;
}

TEST(BearingDensityTest, PeakIsTheHeavierBearingWhateverTheRange) {
  // The mixture mean of these two would lie between them; the density points at the heavier.
  const std::vector<TransmitterHypothesis> ring = {at_bearing(31.0, 20.0, 0.3), at_bearing(201.0, 55.0, 0.7)};
  const BearingDensity d(ring, 35.0 * kDeg);
  EXPECT_NEAR(wrap_angle(d.peak() - 201.0 * kDeg), 0.0, 2.5 * kDeg);
  EXPECT_GT(d.at(201.0 * kDeg), d.at(31.0 * kDeg));
  EXPECT_DOUBLE_EQ(d.at(202.0 * kDeg), d.at(202.0 * kDeg - 2.0 * kPi));  // angles wrap
}

TEST(BearingDensityTest, AnArcCountsAsOneDirection) {
  // 0.6 spread over an arc of 81-101 degrees (0.12 each) against 0.4 at 271 degrees: each
  // arc component is lighter, but the kernel sums the arc, so the arc wins.
  std::vector<TransmitterHypothesis> mixture;
  for (double b = 81.0; b <= 101.0; b += 5.0) mixture.push_back(at_bearing(b, 40.0, 0.12));
  mixture.push_back(at_bearing(271.0, 40.0, 0.4));
  const BearingDensity smoothed(mixture, 35.0 * kDeg);
  EXPECT_NEAR(wrap_angle(smoothed.peak() - 91.0 * kDeg), 0.0, 5.0 * kDeg);
  // With a kernel narrower than a bin the single heavy component wins instead.
  const BearingDensity sharp(mixture, 1.0 * kDeg);
  EXPECT_NEAR(wrap_angle(sharp.peak() - 271.0 * kDeg), 0.0, 2.5 * kDeg);
}

TEST(BearingDensityTest, ComponentOnTheReceiverHasNoBearing) {
  std::vector<TransmitterHypothesis> mixture = {at_bearing(0.0, 0.0, 0.9), at_bearing(-119.0, 30.0, 0.1)};
  const BearingDensity d(mixture, 35.0 * kDeg);
  EXPECT_NEAR(wrap_angle(d.peak() + 119.0 * kDeg), 0.0, 2.5 * kDeg);
  EXPECT_NEAR(d.at(-119.0 * kDeg), 0.1, 1e-3);  // only the bearing-carrying mass
}

TEST(BearingDensityTest, BearingAcrossMinusPiIsOneDirection) {
  // Components either side of +-180 degrees must add up, not fall into two far-apart bins.
  std::vector<TransmitterHypothesis> mixture = {at_bearing(178.0, 40.0, 0.3), at_bearing(-178.0, 40.0, 0.3),
                                       at_bearing(0.0, 40.0, 0.4)};
  const BearingDensity d(mixture, 20.0 * kDeg);
  EXPECT_NEAR(std::abs(wrap_angle(d.peak())), kPi, 5.0 * kDeg);
}

TEST(BearingDensityTest, AgreementWithTheTrueBearing) {
  // A uniform ring says nothing about the bearing: a quarter of the mass within 45 deg.
  std::vector<TransmitterHypothesis> ring;
  for (int b = 0; b < 360; b += 10) ring.push_back(at_bearing(b + 5.0, 50.0, 1.0 / 36.0));
  const BearingAgreement none = bearing_agreement(ring, 0.3);
  EXPECT_NEAR(none.mass_within_45deg, 0.25, 1.0 / 36.0 + 1e-9);
  EXPECT_NEAR(none.mean_cosine, 0.0, 1e-9);
  // 0.8 at 10 deg from the truth, 0.2 behind it; weights need not be normalised.
  const std::vector<TransmitterHypothesis> two = {at_bearing(40.0, 30.0, 1.6), at_bearing(210.0, 30.0, 0.4)};
  const BearingAgreement a = bearing_agreement(two, 30.0 * kDeg);
  EXPECT_NEAR(a.mass_within_45deg, 0.8, 1e-12);
  EXPECT_NEAR(a.mean_cosine, 0.8 * std::cos(10.0 * kDeg) - 0.2, 1e-12);
}

}  // namespace
}  // namespace sarloc::avalanche
