// The Kalman filter on the moment (seed 000, Algorithm 3): its gain is the Jacobian of the
// measurement model, its update is the Gaussian conditional, its likelihood the sign-invariant
// mixture the SOG filter uses.
#include "sarloc/core/avalanche/moment_kalman.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"

namespace sarloc::avalanche {
namespace {

const FieldNoiseModel kNoise{0.05, 2e-9};  // relative 5 %, the floor each test states

TEST(MomentKalmanTest, GainIsTheMeasurementModel) {
  const Vec3 psi(0.05, -0.03, 1.2);
  const Vec3 p(6.0, -3.0, -2.0);
  const Vec3 m(0.01, -0.004, 0.02);
  StateVec x;
  x << psi, p, m;
  const Vec3 expected = MeasurementModel::h(x, DispVec::Zero());
  const Vec3 got = moment_gain(rotation_from_rpy(psi), p) * m;
  EXPECT_LT((got - expected).norm(), 1e-12 * expected.norm());
}

// The update is the Gaussian conditional of m given z, and the likelihood the mixture
// (N(z; C m, S) + N(-z; C m, S)) / 2 up to its constants.
TEST(MomentKalmanTest, UpdateIsTheConditionalAndLikelihoodIsSignInvariant) {
  const Mat3 c = moment_gain(rotation_from_rpy(Vec3(0.0, 0.1, -0.4)), Vec3(4.0, 2.0, -1.5));
  const Vec3 m0(0.012, -0.006, 0.009);
  const Mat3 m_cov = Vec3(4e-5, 9e-5, 1e-5).asDiagonal();
  const Vec3 floor = Vec3::Constant(2e-9);
  const Vec3 z = c * Vec3(0.015, -0.002, 0.011);
  Vec3 m = m0;
  Mat3 M = m_cov;
  const MomentUpdate plus = update_moment(c, m, M, z, floor, 0b111, kNoise);
  ASSERT_TRUE(plus.ok);
  // Brute force: the same noise, the conditional of a joint Gaussian.
  const Vec3 h = c * m0;
  const Vec3 sigma = Vec3::Constant(0.05 * h.norm()) + floor;
  const Mat3 s = c * m_cov * c.transpose() + Mat3(sigma.cwiseAbs2().asDiagonal());
  const Mat3 k = m_cov * c.transpose() * s.inverse();
  EXPECT_LT((m - (m0 + k * (z - h))).norm(), 1e-9 * m0.norm());
  EXPECT_LT((M - (m_cov - k * c * m_cov)).norm(), 1e-9 * m_cov.norm());
  const double nis = (z - h).dot(s.inverse() * (z - h));
  EXPECT_NEAR(plus.nis, nis, 1e-9 * nis);
  const double nis_minus = (-z - h).dot(s.inverse() * (-z - h));
  EXPECT_NEAR(plus.ll, std::log(std::exp(-0.5 * nis) + std::exp(-0.5 * nis_minus)) - 0.5 * std::log(s.determinant()),
              1e-9);
  // -z explains it equally: the same likelihood, and m moves to the same place.
  Vec3 m2 = m0;
  Mat3 M2 = m_cov;
  const MomentUpdate minus = update_moment(c, m2, M2, -z, floor, 0b111, kNoise);
  EXPECT_NEAR(minus.ll, plus.ll, 1e-9);
  EXPECT_LT((m2 - m).norm(), 1e-12);
}

TEST(MomentKalmanTest, AnInvalidAxisIsNoObservation) {
  const Mat3 c = moment_gain(Mat3::Identity(), Vec3(3.0, 1.0, -2.0));
  const Vec3 m0(0.01, 0.01, -0.01);
  const Mat3 m_cov = Mat3::Identity() * 1e-5;
  const Vec3 floor = Vec3::Constant(2e-9);
  Vec3 z = c * Vec3(0.012, 0.008, -0.011);
  Vec3 m_a = m0, m_b = m0;
  Mat3 M_a = m_cov, M_b = m_cov;
  const MomentUpdate a = update_moment(c, m_a, M_a, valid_axes_only(z, 0b011), floor, 0b011, kNoise);
  z.z() = 1.0;  // whatever the invalid axis holds
  const MomentUpdate b = update_moment(c, m_b, M_b, valid_axes_only(z, 0b011), floor, 0b011, kNoise);
  EXPECT_DOUBLE_EQ(a.ll, b.ll);
  EXPECT_EQ(m_a, m_b);
}

TEST(MomentKalmanTest, AZeroCovarianceIsAPointHypothesis) {
  const Mat3 c = moment_gain(Mat3::Identity(), Vec3(3.0, 1.0, -2.0));
  Vec3 m(0.01, 0.01, -0.01);
  Mat3 M = Mat3::Zero();
  const Vec3 before = m;
  const MomentUpdate u = update_moment(c, m, M, c * Vec3(0.011, 0.01, -0.01), Vec3::Constant(2e-9), 0b111, kNoise);
  EXPECT_TRUE(u.ok);
  EXPECT_EQ(m, before) << "a particle that samples m is weighted, not updated";
}

}  // namespace
}  // namespace sarloc::avalanche
