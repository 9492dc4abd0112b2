#pragma once
// Magnetic dipole measurement model and robocentric composition (seed 000, section II).
//
// State of one transmitter hypothesis (one Gaussian of the SOG filter, seed 000 eq. (1), (3)):
//   x = [Psi (roll, pitch, yaw of R_k in G_k), p (transmitter in G_k), m (moment in G_k)]  (9)
// Displacement between two measurements (eq. (4)):
//   d = [t (translation of R_k in R_{k-1}), dPsi (rpy of R_k in R_{k-1})]                  (6)
// Augmented state x* = [x; d] (eq. (10)).
//
// Measurement (eq. (12)-(14)): r = R(Psi) t - p is the transmitter -> receiver vector in
// G_{k-1}, H_G = (3 (m.r) r / r^2 - m) / (4 pi r^3) = A m / (4 pi r^5), and
//   z = h(x, d) = R_k^T H_G,   R_k = R(Psi) R(dPsi).
// Composition (eq. (9)): Psi_k = rpy(R(Psi) R(dPsi)), p_k = p - R(Psi) t, m_k = m.
//
// Jacobians are optional outputs (J_out_in naming); each one is checked against central
// differences in tests/unit/avalanche/dipole_model_test.cpp.
//
// Usage:
//   Jacobian<3, 9> H_x; Jacobian<3, 6> H_d;
//   Vec3 z_pred = MeasurementModel::h(x, d, &H_x, &H_d);      // one call
//   const MeasurementModel model(d);                          // one filter step: d-dependent
//   for (...) z_pred_i = model.h(x_i, &H_x, &H_d);            // quantities computed once
//   CompositionJacobians J;                                   // F_x, F_d by blocks
//   StateVec x_next = CompositionModel::f(x, d, &J);
#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

/// Named indices into the 9-state x and the 6-vector d (never magic numbers).
namespace idx {
inline constexpr int kAtt = 0;   ///< roll, pitch, yaw of R_k in G_k (rad)
inline constexpr int kPos = 3;   ///< transmitter position in G_k (m)
inline constexpr int kMom = 6;   ///< magnetic moment in G_k (A m^2)
inline constexpr int kStateDim = 9;
inline constexpr int kTrans = 0;  ///< displacement translation in R_{k-1} (m)
inline constexpr int kRot = 3;    ///< displacement rotation rpy of R_k in R_{k-1} (rad)
inline constexpr int kDispDim = 6;
inline constexpr int kAugDim = kStateDim + kDispDim;  ///< x* = [x; d], eq. (10)
}  // namespace idx

using StateVec = Eigen::Matrix<double, idx::kStateDim, 1>;
using StateCov = Eigen::Matrix<double, idx::kStateDim, idx::kStateDim>;
using DispVec = Vec6;
using DispCov = Mat6;
using AugVec = Eigen::Matrix<double, idx::kAugDim, 1>;

/// Field of a point magnetic dipole, eq. (12)-(13): H = A(r) m / (4 pi r^5).
struct DipoleField {
  /// r: transmitter -> observation point (m), m: moment (A m^2). Returns H (A/m).
  /// J_H_r = dH/dr, J_H_m = dH/dm = A / (4 pi r^5). r must be non-zero.
  static Vec3 field(const Vec3& r, const Vec3& m, Mat3* J_H_r = nullptr, Mat3* J_H_m = nullptr);

  /// Inverse of eq. (12) for the moment: m = 4 pi r^3 (1.5 r r^T / r^2 - I) H (used to initialise
  /// each Gaussian, seed 000 section III-B). J_m_r = dm/dr, J_m_H = dm/dH.
  static Vec3 moment(const Vec3& r, const Vec3& h, Mat3* J_m_r = nullptr, Mat3* J_m_H = nullptr);

  /// What a receiver resolves of the field at wavenumber k (rad/m): the major axis of the
  /// polarisation ellipse of the full dipole field, principal_axis(full_dipole_field(r, m, k))
  /// of receiver_model.hpp, in closed form. With Q = field(r, m), the full field is A + j B,
  /// A = Q + k^2 (m - n (n.m)) / (4 pi r) (the radiation term), B = k r Q (the induction term),
  /// and the major axis is A cos(theta) + B sin(theta), theta = atan2(2 A.B, |A|^2 - |B|^2) / 2.
  /// Its magnitude is |Q| sqrt(1 + (k r)^2) along the moment and |Q| sqrt(1 - (k r)^2 + (k r)^4)
  /// across it: 0.5 % from Q at 10 m, 11 % at 50 m from a 457 kHz transmitter. k = 0 gives
  /// field() exactly. J_r = dv/dr, J_m = dv/dm.
  static Vec3 major_axis(const Vec3& r, const Vec3& m, double k, Mat3* J_r = nullptr, Mat3* J_m = nullptr);

  /// The moment whose major_axis(r, m, k) is h: Newton steps from moment(r, h) (k = 0: moment()
  /// exactly). J_m_r = dm/dr, J_m_H = dm/dh at that moment (implicit function theorem).
  static Vec3 moment_of_major_axis(const Vec3& r, const Vec3& h, double k, Mat3* J_m_r = nullptr,
                                   Mat3* J_m_H = nullptr);
};

/// Measurement function h of eq. (14) on the augmented state x* = [x; d].
///
/// An object holds what depends on the displacement d only, t, R(dPsi) and E_w(dPsi), shared
/// by every Gaussian of one filter step (the SOG filter builds one per step and calls the
/// member h for each component); the static h(x, d, ...) is the same computation in one call.
class MeasurementModel {
 public:
  /// Caches t, R(dPsi) and E_w(dPsi) of the displacement d (eq. (4)). wavenumber: the field
  /// the receiver resolves at that carrier (DipoleField::major_axis); 0: the quasi-static
  /// field of eq. (12).
  explicit MeasurementModel(const DispVec& d, double wavenumber = 0.0);

  /// z = h(x, d) for the displacement given at construction, with H_x = dh/dx (3x9) and
  /// H_d = dh/dd (3x6). The SOG filter's entry point.
  Vec3 h(const StateVec& x, Jacobian<3, idx::kStateDim>* H_x = nullptr,
         Jacobian<3, idx::kDispDim>* H_d = nullptr) const;

  /// Convenience: MeasurementModel(d).h(x, H_x, H_d).
  static Vec3 h(const StateVec& x, const DispVec& d, Jacobian<3, idx::kStateDim>* H_x = nullptr,
                Jacobian<3, idx::kDispDim>* H_d = nullptr, double wavenumber = 0.0);
  /// Same on x* = [x; d] with one 3x15 Jacobian [H_x H_d] (tests, documentation).
  static Vec3 h(const AugVec& xa, Jacobian<3, idx::kAugDim>* H = nullptr, double wavenumber = 0.0);

 private:
  Vec3 t_;    ///< translation of R_k in R_{k-1}
  Mat3 r_d_;  ///< R(dPsi)
  Mat3 e_d_;  ///< E_w(dPsi)
  double k_ = 0.0;  ///< wavenumber of the carrier (rad/m); 0: quasi-static
};

/// The Jacobians of the composition f (eq. (9), (15)) by their non-trivial blocks. Every
/// other block is an identity or zero (m_k = m, p_k is linear in p, Psi_k does not depend on
/// p, m or t):
///   F_x = d f / d x = [[A, 0, 0], [C, I, 0], [0, 0, I]]   (rows, columns: Psi, p, m)
///   F_d = d f / d d = [[0, D], [T, 0], [0, 0]]             (columns: t, dPsi)
/// so F P F^T can be formed block by block, never as a dense 15x15 product. F_x() and F_d()
/// expand them (tests and the dense convenience overload of CompositionModel::f).
struct CompositionJacobians {
  Mat3 att_att;    ///< A = dPsi_k/dPsi = E_w(Psi_k)^-1 E_w(Psi)
  Mat3 pos_att;    ///< C = dp_k/dPsi = [R(Psi) t]x E_w(Psi)
  Mat3 att_rot;    ///< D = dPsi_k/ddPsi = E_w(Psi_k)^-1 R(Psi) E_w(dPsi)
  Mat3 pos_trans;  ///< T = dp_k/dt = -R(Psi)
  StateCov F_x() const;
  Jacobian<idx::kStateDim, idx::kDispDim> F_d() const;
};

/// Composition function f of eq. (9) / (15): Psi_k = rpy(R(Psi) R(dPsi)), p_k = p - R(Psi) t,
/// m_k = m. Each call depends on its own d (the SOG filter composes at each Gaussian's
/// posterior displacement), so nothing is cached across calls; the trigonometry of Psi and
/// dPsi is computed once per call (EulerTrig) and E_w(Psi_k)^-1 comes from R_k without any
/// trigonometric call (EulerTrig::from_rotation).
struct CompositionModel {
  /// The SOG filter's entry point: f with its Jacobians by blocks (J may be null).
  static StateVec f(const StateVec& x, const DispVec& d, CompositionJacobians* J);
  /// Same with dense F_x (9x9) and F_d (9x6).
  static StateVec f(const StateVec& x, const DispVec& d, StateCov* F_x = nullptr,
                    Jacobian<idx::kStateDim, idx::kDispDim>* F_d = nullptr);
  /// Same on x* = [x; d] with one 9x15 Jacobian F = [F_x F_d].
  static StateVec f(const AugVec& xa, Jacobian<idx::kStateDim, idx::kAugDim>* F = nullptr);
  /// The pose part of f on a rotation matrix the caller keeps (the particle filters, which
  /// compose thousands of poses a step): R(Psi) <- R(Psi) R(dPsi), p <- p - R(Psi) t. The Euler
  /// angles of the result are rpy_from_rotation(rotation).
  static void compose_pose(Mat3& rotation, Vec3& p, const DispVec& d);
};

/// Composition of two displacements d1 (R_{a} -> R_{b}) then d2 (R_{b} -> R_{c}) into
/// R_{a} -> R_{c}: t = t1 + R(dPsi1) t2, R = R(dPsi1) R(dPsi2). Used by OdometryAccumulator.
DispVec compose_displacements(const DispVec& d1, const DispVec& d2, Mat6* J_d1 = nullptr,
                              Mat6* J_d2 = nullptr);

}  // namespace sarloc::avalanche
