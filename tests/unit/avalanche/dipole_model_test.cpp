// Every analytic Jacobian of the avalanche models against central differences, at zero,
// tiny and random inputs (one shared helper: tests/support/numeric_jacobian.hpp).
#include "sarloc/core/avalanche/dipole_model.hpp"

#include <gtest/gtest.h>

#include <random>

#include "sarloc/core/avalanche/receiver_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "support/numeric_jacobian.hpp"

namespace sarloc::avalanche {
namespace {

using test::numeric_jacobian;
using test::relative_error;

// Kinds of operating point every Jacobian is checked at.
enum class Point { kZero, kTiny, kRandom };

struct Sampler {
  std::mt19937_64 rng{42};
  double u(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  Vec3 angles(Point k) {
    if (k == Point::kZero) return Vec3::Zero();
    if (k == Point::kTiny) return Vec3(1e-7, -2e-7, 3e-7);
    return Vec3(u(-0.4, 0.4), u(-0.4, 0.4), u(-3.0, 3.0));
  }
  Vec3 translation(Point k) {
    if (k == Point::kZero) return Vec3::Zero();
    if (k == Point::kTiny) return Vec3(1e-7, 2e-7, -1e-7);
    return Vec3(u(-1.5, 1.5), u(-1.5, 1.5), u(-0.2, 0.2));
  }
  Vec3 position() {  // transmitter 0.8 .. 60 m away, below the receiver
    const double range = std::exp(u(std::log(0.8), std::log(60.0)));
    const double az = u(-kPi, kPi);
    const double el = u(-1.4, -0.05);
    return range * Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  }
  Vec3 moment() { return 0.02 * Vec3(u(-1, 1), u(-1, 1), u(-1, 1)); }
};

constexpr Point kPoints[] = {Point::kZero, Point::kTiny, Point::kRandom};
constexpr int kRandomRepeats = 25;

TEST(RotationTest, RoundTripAndEulerRates) {
  Sampler s;
  for (int i = 0; i < 50; ++i) {
    const Vec3 a = s.angles(Point::kRandom);
    EXPECT_LT((rpy_from_rotation(rotation_from_rpy(a)) - a).norm(), 1e-12);
    EXPECT_LT((world_to_euler_rate(a) * euler_rate_to_world(a) - Mat3::Identity()).norm(), 1e-12);
    // dR = [E_w dPsi]x R for each Euler-rate direction.
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-6;
      Vec3 ap = a, am = a;
      ap[k] += h;
      am[k] -= h;
      const Mat3 dr = (rotation_from_rpy(ap) - rotation_from_rpy(am)) / (2 * h);
      const Mat3 expect = skew(euler_rate_to_world(a).col(k)) * rotation_from_rpy(a);
      EXPECT_LT((dr - expect).cwiseAbs().maxCoeff(), 1e-8);
    }
  }
  EXPECT_NEAR(wrap_angle(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(wrap_angle(-kPi / 2 - 2 * kPi), -kPi / 2, 1e-12);
}

TEST(DipoleFieldTest, MatchesClosedFormOnAxisAndEquator) {
  const Vec3 m(0.0, 0.0, 0.02);
  // On axis: |H| = 2 m / (4 pi r^3); equator: |H| = m / (4 pi r^3), opposite to m.
  const Vec3 axis = DipoleField::field(Vec3(0, 0, 10), m);
  const Vec3 equator = DipoleField::field(Vec3(10, 0, 0), m);
  EXPECT_NEAR(axis.z(), 2 * 0.02 / (4 * kPi * 1000), 1e-15);
  EXPECT_NEAR(equator.z(), -0.02 / (4 * kPi * 1000), 1e-15);
  EXPECT_NEAR(axis.head<2>().norm(), 0.0, 1e-18);
}

TEST(DipoleFieldTest, JacobiansMatchNumeric) {
  Sampler s;
  for (int i = 0; i < kRandomRepeats; ++i) {
    const Vec3 r = -s.position();
    const Vec3 m = s.moment();
    Mat3 j_r, j_m;
    DipoleField::field(r, m, &j_r, &j_m);
    const auto nr = numeric_jacobian<3, 3>([&](const Vec3& v) { return DipoleField::field(v, m); },
                                           r, 1e-6);
    const auto nm = numeric_jacobian<3, 3>([&](const Vec3& v) { return DipoleField::field(r, v); },
                                           m, Vec3::Constant(1e-5));
    EXPECT_LT(relative_error(j_r, nr), 1e-6) << "r = " << r.transpose();
    EXPECT_LT(relative_error(j_m, nm), 1e-8);
  }
}

TEST(DipoleFieldTest, MomentInvertsFieldWithJacobians) {
  Sampler s;
  for (int i = 0; i < kRandomRepeats; ++i) {
    const Vec3 r = -s.position();
    const Vec3 m = s.moment();
    const Vec3 h = DipoleField::field(r, m);
    Mat3 j_r, j_h;
    const Vec3 back = DipoleField::moment(r, h, &j_r, &j_h);
    EXPECT_LT((back - m).norm(), 1e-10 * m.norm());
    const auto nr = numeric_jacobian<3, 3>([&](const Vec3& v) { return DipoleField::moment(v, h); },
                                           r, 1e-6);
    const auto nh = numeric_jacobian<3, 3>([&](const Vec3& v) { return DipoleField::moment(r, v); },
                                           h, Vec3::Constant(1e-3 * h.norm()));
    EXPECT_LT(relative_error(j_r, nr), 1e-6);
    EXPECT_LT(relative_error(j_h, nh), 1e-7);
  }
}

// The wavenumber of the EN 300 718 carrier, 457 kHz.
const double kCarrierK = carrier_wavenumber(457000.0);

// The closed form is what the receiver model resolves of the full field (up to the sign, which a
// pulse's carrier phase sets), at 0.8-60 m and out to 100 m, where k r is 1.
TEST(DipoleFieldTest, MajorAxisIsWhatTheReceiverResolvesOfTheFullField) {
  Sampler s;
  for (int i = 0; i < 200; ++i) {
    const Vec3 r = -s.position() * (i % 4 == 0 ? 1.6 : 1.0);
    const Vec3 m = s.moment();
    const Vec3 v = DipoleField::major_axis(r, m, kCarrierK);
    const Vec3 resolved = principal_axis(full_dipole_field(r, m, kCarrierK));
    EXPECT_LT(std::min((v - resolved).norm(), (v + resolved).norm()), 1e-12 * v.norm()) << "r = " << r.transpose();
  }
  // On the moment's axis and across it, the magnitudes of the documentation.
  const Vec3 m(0.0, 0.0, 0.02);
  const double kr2 = std::pow(kCarrierK * 50.0, 2);
  EXPECT_NEAR(DipoleField::major_axis(Vec3(0, 0, 50), m, kCarrierK).norm(),
              DipoleField::field(Vec3(0, 0, 50), m).norm() * std::sqrt(1.0 + kr2), 1e-15);
  EXPECT_NEAR(DipoleField::major_axis(Vec3(50, 0, 0), m, kCarrierK).norm(),
              DipoleField::field(Vec3(50, 0, 0), m).norm() * std::sqrt(1.0 - kr2 + kr2 * kr2), 1e-15);
  EXPECT_EQ(DipoleField::major_axis(Vec3(3, 1, -2), m, 0.0), DipoleField::field(Vec3(3, 1, -2), m));
}

TEST(DipoleFieldTest, MajorAxisJacobiansMatchNumeric) {
  Sampler s;
  for (int i = 0; i < kRandomRepeats; ++i) {
    const Vec3 r = -s.position();
    const Vec3 m = s.moment();
    Mat3 j_r, j_m;
    DipoleField::major_axis(r, m, kCarrierK, &j_r, &j_m);
    const auto nr =
        numeric_jacobian<3, 3>([&](const Vec3& v) { return DipoleField::major_axis(v, m, kCarrierK); }, r, 1e-6);
    const auto nm = numeric_jacobian<3, 3>([&](const Vec3& v) { return DipoleField::major_axis(r, v, kCarrierK); }, m,
                                           Vec3::Constant(1e-5));
    EXPECT_LT(relative_error(j_r, nr), 1e-6) << "r = " << r.transpose();
    EXPECT_LT(relative_error(j_m, nm), 1e-7) << "r = " << r.transpose();
  }
}

TEST(DipoleFieldTest, MomentOfMajorAxisInvertsItWithJacobians) {
  Sampler s;
  for (int i = 0; i < kRandomRepeats; ++i) {
    const Vec3 r = -s.position();
    const Vec3 m = s.moment();
    const Vec3 h = DipoleField::major_axis(r, m, kCarrierK);
    Mat3 j_r, j_h;
    const Vec3 back = DipoleField::moment_of_major_axis(r, h, kCarrierK, &j_r, &j_h);
    EXPECT_LT((back - m).norm(), 1e-10 * m.norm()) << "r = " << r.transpose();
    const auto nr = numeric_jacobian<3, 3>(
        [&](const Vec3& v) { return DipoleField::moment_of_major_axis(v, h, kCarrierK); }, r, 1e-6);
    const auto nh =
        numeric_jacobian<3, 3>([&](const Vec3& v) { return DipoleField::moment_of_major_axis(r, v, kCarrierK); }, h,
                               Vec3::Constant(1e-3 * h.norm()));
    EXPECT_LT(relative_error(j_r, nr), 1e-6);
    EXPECT_LT(relative_error(j_h, nh), 1e-6);
  }
}

AugVec make_aug(Sampler& s, Point k) {
  AugVec xa;
  xa << s.angles(k), s.position(), s.moment(), s.translation(k), s.angles(k);
  if (k == Point::kRandom) xa.segment<3>(idx::kStateDim + idx::kRot).z() *= 0.3;
  return xa;
}

AugVec steps_for(const AugVec& xa) {
  AugVec st = AugVec::Constant(1e-6);
  st.segment<3>(idx::kMom) = Vec3::Constant(1e-6 * std::max(1e-3, xa.segment<3>(idx::kMom).norm()));
  return st;
}

TEST(MeasurementModelTest, JacobianMatchesNumericAtZeroTinyRandom) {
  Sampler s;
  for (Point k : kPoints) {
    for (int i = 0; i < (k == Point::kRandom ? kRandomRepeats : 5); ++i) {
      const AugVec xa = make_aug(s, k);
      Jacobian<3, idx::kAugDim> h;
      const Vec3 z = MeasurementModel::h(xa, &h);
      const auto n = numeric_jacobian<3, idx::kAugDim>(
          [](const AugVec& v) { return MeasurementModel::h(v); }, xa, steps_for(xa));
      EXPECT_LT(relative_error(h, n), 2e-6) << "x* = " << xa.transpose();
      // The split version agrees with the 3x15 one.
      Jacobian<3, idx::kStateDim> h_x;
      Jacobian<3, idx::kDispDim> h_d;
      const Vec3 z2 = MeasurementModel::h(StateVec(xa.head<9>()), DispVec(xa.tail<6>()), &h_x, &h_d);
      EXPECT_EQ(z, z2);
      EXPECT_EQ(h.leftCols<9>(), h_x);
      EXPECT_EQ(h.rightCols<6>(), h_d);
    }
  }
}

// The same at the carrier: the field the receiver resolves (DipoleField::major_axis).
TEST(MeasurementModelTest, JacobianMatchesNumericAtTheCarrier) {
  Sampler s;
  for (Point k : kPoints) {
    for (int i = 0; i < (k == Point::kRandom ? kRandomRepeats : 5); ++i) {
      const AugVec xa = make_aug(s, k);
      Jacobian<3, idx::kAugDim> h;
      MeasurementModel::h(xa, &h, kCarrierK);
      const auto n = numeric_jacobian<3, idx::kAugDim>(
          [](const AugVec& v) { return MeasurementModel::h(v, nullptr, kCarrierK); }, xa, steps_for(xa));
      EXPECT_LT(relative_error(h, n), 2e-6) << "x* = " << xa.transpose();
    }
  }
}

// The SOG filter's entry point: one MeasurementModel per step (d cached), h per component.
// Perturbing d rebuilds the model, so the cached R(dPsi), E_w(dPsi) are differentiated too.
TEST(MeasurementModelTest, CachedModelJacobiansMatchNumericAtZeroTinyRandom) {
  Sampler s;
  for (Point k : kPoints) {
    for (int i = 0; i < (k == Point::kRandom ? kRandomRepeats : 5); ++i) {
      const AugVec xa = make_aug(s, k);
      const StateVec x = xa.head<idx::kStateDim>();
      const DispVec d = xa.tail<idx::kDispDim>();
      const MeasurementModel model(d);
      Jacobian<3, idx::kStateDim> h_x;
      Jacobian<3, idx::kDispDim> h_d;
      const Vec3 z = model.h(x, &h_x, &h_d);
      Jacobian<3, idx::kAugDim> h;
      h << h_x, h_d;
      const auto n = numeric_jacobian<3, idx::kAugDim>(
          [](const AugVec& v) {
            return MeasurementModel(DispVec(v.tail<idx::kDispDim>()))
                .h(StateVec(v.head<idx::kStateDim>()));
          },
          xa, steps_for(xa));
      EXPECT_LT(relative_error(h, n), 2e-6) << "x* = " << xa.transpose();
      // Without Jacobians, and through the static convenience: the same numbers.
      EXPECT_EQ(model.h(x), z);
      EXPECT_EQ(MeasurementModel::h(x, d), z);
    }
  }
}

TEST(MeasurementModelTest, MatchesDirectFieldAtZeroDisplacement) {
  Sampler s;
  AugVec xa = make_aug(s, Point::kRandom);
  xa.tail<6>().setZero();
  const Vec3 p = xa.segment<3>(idx::kPos);
  const Vec3 m = xa.segment<3>(idx::kMom);
  const Vec3 expect =
      rotation_from_rpy(xa.segment<3>(idx::kAtt)).transpose() * DipoleField::field(-p, m);
  EXPECT_LT((MeasurementModel::h(xa) - expect).norm(), 1e-12 * expect.norm());
}

TEST(CompositionModelTest, JacobianMatchesNumericAtZeroTinyRandom) {
  Sampler s;
  for (Point k : kPoints) {
    for (int i = 0; i < (k == Point::kRandom ? kRandomRepeats : 5); ++i) {
      const AugVec xa = make_aug(s, k);
      Jacobian<idx::kStateDim, idx::kAugDim> f;
      CompositionModel::f(xa, &f);
      const auto n = numeric_jacobian<idx::kStateDim, idx::kAugDim>(
          [](const AugVec& v) { return CompositionModel::f(v); }, xa, steps_for(xa));
      EXPECT_LT(relative_error(f, n), 1e-6) << "x* = " << xa.transpose();
    }
  }
}

// The SOG filter's entry point: f with its Jacobians by blocks. The expanded F_x, F_d are
// compared with central differences whole, so the blocks taken as identity or zero are checked
// as well as A, C, D, T.
TEST(CompositionModelTest, BlockJacobiansMatchNumericAtZeroTinyRandom) {
  Sampler s;
  for (Point k : kPoints) {
    for (int i = 0; i < (k == Point::kRandom ? kRandomRepeats : 5); ++i) {
      const AugVec xa = make_aug(s, k);
      const StateVec x = xa.head<idx::kStateDim>();
      const DispVec d = xa.tail<idx::kDispDim>();
      CompositionJacobians j;
      const StateVec out = CompositionModel::f(x, d, &j);
      Jacobian<idx::kStateDim, idx::kAugDim> f;
      f << j.F_x(), j.F_d();
      const auto n = numeric_jacobian<idx::kStateDim, idx::kAugDim>(
          [](const AugVec& v) {
            return CompositionModel::f(StateVec(v.head<idx::kStateDim>()),
                                       DispVec(v.tail<idx::kDispDim>()),
                                       static_cast<CompositionJacobians*>(nullptr));
          },
          xa, steps_for(xa));
      EXPECT_LT(relative_error(f, n), 1e-6) << "x* = " << xa.transpose();
      // The dense overloads are the same numbers.
      StateCov f_x;
      Jacobian<idx::kStateDim, idx::kDispDim> f_d;
      EXPECT_EQ(CompositionModel::f(x, d, &f_x, &f_d), out);
      EXPECT_EQ(f_x, j.F_x());
      EXPECT_EQ(f_d, j.F_d());
      EXPECT_EQ(CompositionModel::f(x, d), out);
    }
  }
}

TEST(CompositionModelTest, MovesTransmitterAgainstTheStep) {
  AugVec xa = AugVec::Zero();
  xa.segment<3>(idx::kAtt) = Vec3(0, 0, kPi / 2);  // receiver faces north
  xa.segment<3>(idx::kPos) = Vec3(0, 10, -2);
  xa.segment<3>(idx::kStateDim + idx::kTrans) = Vec3(1, 0, 0);  // one step forward
  const StateVec x = CompositionModel::f(xa);
  EXPECT_LT((x.segment<3>(idx::kPos) - Vec3(0, 9, -2)).norm(), 1e-12);
}

TEST(CompositionModelTest, ComposePoseOnARotationMatrixIsF) {
  // The particle filters' entry point must be the very composition the SOG filter runs.
  std::mt19937_64 rng{7};
  auto u = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  for (int trial = 0; trial < 50; ++trial) {
    StateVec x;
    x << u(-0.3, 0.3), u(-0.3, 0.3), u(-3.0, 3.0), u(-40, 40), u(-40, 40), u(-5, 0), u(-0.02, 0.02),
        u(-0.02, 0.02), u(-0.02, 0.02);
    DispVec d;
    d << u(-1.5, 1.5), u(-1.5, 1.5), u(-0.2, 0.2), u(-0.1, 0.1), u(-0.1, 0.1), u(-1.0, 1.0);
    const StateVec expected = CompositionModel::f(x, d, static_cast<CompositionJacobians*>(nullptr));
    Mat3 rotation = rotation_from_rpy(x.segment<3>(idx::kAtt));
    Vec3 p = x.segment<3>(idx::kPos);
    CompositionModel::compose_pose(rotation, p, d);
    EXPECT_LT((p - expected.segment<3>(idx::kPos)).norm(), 1e-12);
    EXPECT_LT((rotation - rotation_from_rpy(expected.segment<3>(idx::kAtt))).norm(), 1e-12);
  }
}

TEST(DisplacementTest, ComposeJacobiansMatchNumeric) {
  Sampler s;
  for (Point k : kPoints) {
    for (int i = 0; i < 10; ++i) {
      DispVec d1, d2;
      d1 << s.translation(k), s.angles(k);
      d2 << s.translation(k), s.angles(k);
      if (k == Point::kRandom) { d1[5] *= 0.3; d2[5] *= 0.3; }
      Mat6 j1, j2;
      compose_displacements(d1, d2, &j1, &j2);
      const auto n1 = numeric_jacobian<6, 6>(
          [&](const DispVec& v) { return compose_displacements(v, d2); }, d1, 1e-6);
      const auto n2 = numeric_jacobian<6, 6>(
          [&](const DispVec& v) { return compose_displacements(d1, v); }, d2, 1e-6);
      EXPECT_LT(relative_error(j1, n1), 1e-6);
      EXPECT_LT(relative_error(j2, n2), 1e-6);
    }
  }
}

}  // namespace
}  // namespace sarloc::avalanche
