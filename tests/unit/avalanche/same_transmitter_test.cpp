// The same-transmitter test: position and moment, the moment up to sign.
#include "sarloc/core/avalanche/same_transmitter.hpp"

#include <gtest/gtest.h>

namespace sarloc::avalanche {
namespace {

MixtureMoments filter_moments(const Vec3& p, const Vec3& m) {
  MixtureMoments x;
  x.mean.segment<3>(idx::kPos) = p;
  x.mean.segment<3>(idx::kMom) = m;
  x.covariance = StateCov::Identity() * 1e-4;
  x.covariance.block<3, 3>(idx::kPos, idx::kPos) = Mat3::Identity() * 0.01;       // 0.1 m
  x.covariance.block<3, 3>(idx::kMom, idx::kMom) = Mat3::Identity() * 1e-6;       // 0.001 A m^2
  return x;
}

// The same state with the moment's sign flipped, its cross-covariances with it too.
MixtureMoments flipped(MixtureMoments x) {
  x.mean.segment<3>(idx::kMom) *= -1.0;
  x.covariance.block<3, 9>(idx::kMom, 0) *= -1.0;
  x.covariance.block<9, 3>(0, idx::kMom) *= -1.0;  // the moment's own block flips twice: unchanged
  return x;
}

TEST(SameTransmitter, DistanceIsTheSummedMahalanobisOfPositionAndMoment) {
  const MixtureMoments a = filter_moments(Vec3(1.0, 2.0, -1.0), Vec3(0.02, 0.0, 0.0));
  const MixtureMoments b = filter_moments(Vec3(1.1, 2.0, -1.0), Vec3(0.02, 0.001, 0.0));
  // Diagonal covariances: 0.1^2 / (2 * 0.01) + 0.001^2 / (2 * 1e-6).
  EXPECT_NEAR(same_transmitter_distance2(a, b), 0.5 + 0.5, 1e-9);
  EXPECT_NEAR(same_transmitter_distance2(b, a), 1.0, 1e-9);
}

TEST(SameTransmitter, TheMomentCountsUpToSign) {
  MixtureMoments a = filter_moments(Vec3(0.0, 15.0, -1.0), Vec3(0.01, -0.005, 0.004));
  // Position and moment correlated, as a filter's are near the transmitter.
  a.covariance.block<3, 3>(idx::kPos, idx::kMom) = Mat3::Identity() * 5e-5;
  a.covariance.block<3, 3>(idx::kMom, idx::kPos) = Mat3::Identity() * 5e-5;
  MixtureMoments b = a;
  b.mean.segment<3>(idx::kPos) += Vec3(0.05, -0.03, 0.02);
  b.mean.segment<3>(idx::kMom) += Vec3(0.0005, 0.0003, -0.0002);
  const double same = same_transmitter_distance2(a, b);
  EXPECT_LT(same, 5.0);
  // The receiver lost the field's sign: a filter holding -m is the same transmitter, and the
  // test must flip the cross-covariances with the moment (without that the value changes).
  EXPECT_NEAR(same_transmitter_distance2(a, flipped(b)), same, 1e-9);
  EXPECT_NEAR(same_transmitter_distance2(flipped(a), b), same, 1e-9);
}

TEST(SameTransmitter, AnotherMomentAtThePlaceIsAnotherTransmitter) {
  const MixtureMoments a = filter_moments(Vec3(0.0, 15.0, -1.0), Vec3(0.02, 0.0, 0.0));
  const MixtureMoments b = filter_moments(Vec3(0.0, 15.0, -1.0), Vec3(0.0, 0.02, 0.0));  // 90 deg away
  EXPECT_GT(same_transmitter_distance2(a, b), 100.0);
  const MixtureMoments c = filter_moments(Vec3(0.0, 15.0, -1.0), Vec3(0.03, 0.0, 0.0));  // 1.5x as strong
  EXPECT_GT(same_transmitter_distance2(a, c), 22.5);  // chi2_6(0.999)
}

TEST(SameTransmitter, UnusableCovariancesTellNothingApart) {
  MixtureMoments a = filter_moments(Vec3::Zero(), Vec3(0.02, 0.0, 0.0));
  MixtureMoments b = filter_moments(Vec3(5.0, 0.0, 0.0), Vec3(0.0, 0.02, 0.0));
  a.covariance.setZero();
  b.covariance.setZero();
  EXPECT_EQ(same_transmitter_distance2(a, b), 0.0);
}

TEST(SameTransmitter, AMomentIsDeterminedWhenItsSpreadIsSmallAgainstItsSize) {
  MixtureMoments a = filter_moments(Vec3::Zero(), Vec3(0.02, 0.0, 0.0));
  EXPECT_TRUE(moment_determined(a, 0.25));  // sqrt(3e-6) = 0.0017 against 0.02
  // A mixture holding both signs: the mean near zero, the spread as large as the moment.
  a.mean.segment<3>(idx::kMom) = Vec3(0.001, 0.0, 0.0);
  a.covariance.block<3, 3>(idx::kMom, idx::kMom) = Mat3::Identity() * 4e-4 / 3.0;
  EXPECT_FALSE(moment_determined(a, 0.25));
}

}  // namespace
}  // namespace sarloc::avalanche
