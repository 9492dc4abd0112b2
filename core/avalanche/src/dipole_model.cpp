#include "sarloc/core/avalanche/dipole_model.hpp"

#include <Eigen/LU>
#include <cmath>

#include "sarloc/core/avalanche/rotation.hpp"

namespace sarloc::avalanche {

Vec3 DipoleField::field(const Vec3& r, const Vec3& m, Mat3* J_H_r, Mat3* J_H_m) {
  const double r2 = r.squaredNorm();
  const double rn = std::sqrt(r2);
  const double inv = 1.0 / (4.0 * kPi * r2 * r2 * rn);  // 1 / (4 pi r^5)
  const double mr = m.dot(r);
  const Vec3 n = 3.0 * mr * r - r2 * m;  // A m, eq. (13)
  if (J_H_r != nullptr) {
    // d(A m)/dr = 3 (r m^T + (m.r) I) - 2 m r^T ; d(r^-5)/dr = -5 r^-7 r^T.
    Mat3 dn = 3.0 * (r * m.transpose()) - 2.0 * (m * r.transpose());
    dn.diagonal().array() += 3.0 * mr;
    *J_H_r = inv * (dn - (5.0 / r2) * (n * r.transpose()));
  }
  if (J_H_m != nullptr) {
    Mat3 a = 3.0 * (r * r.transpose());
    a.diagonal().array() -= r2;
    *J_H_m = inv * a;
  }
  return inv * n;
}

Vec3 DipoleField::moment(const Vec3& r, const Vec3& h, Mat3* J_m_r, Mat3* J_m_H) {
  // B(r) = A / (4 pi r^5) has inverse 4 pi r^3 (1.5 r r^T / r^2 - I).
  const double r2 = r.squaredNorm();
  const double rn = std::sqrt(r2);
  Mat3 b_inv = (1.5 / r2) * (r * r.transpose());
  b_inv.diagonal().array() -= 1.0;
  b_inv *= 4.0 * kPi * r2 * rn;
  const Vec3 m = b_inv * h;
  if (J_m_r != nullptr) {
    // m = B^-1 h with h fixed: dm = -B^-1 (dB m) = -B^-1 J_H_r(r, m) dr.
    Mat3 j_h_r;
    DipoleField::field(r, m, &j_h_r, nullptr);
    *J_m_r = -b_inv * j_h_r;
  }
  if (J_m_H != nullptr) *J_m_H = b_inv;
  return m;
}

Vec3 DipoleField::major_axis(const Vec3& r, const Vec3& m, double k, Mat3* J_r, Mat3* J_m) {
  const bool need = J_r != nullptr || J_m != nullptr;
  Mat3 jq_r, jq_m;
  const Vec3 q = field(r, m, need ? &jq_r : nullptr, need ? &jq_m : nullptr);
  if (k == 0.0) {
    if (J_r != nullptr) *J_r = jq_r;
    if (J_m != nullptr) *J_m = jq_m;
    return q;
  }
  const double rho2 = r.squaredNorm();
  const double rho = std::sqrt(rho2);
  const double kappa = k * k / (4.0 * kPi);
  const double rm = r.dot(m);
  const Vec3 a = q + kappa * (m / rho - r * (rm / (rho2 * rho)));
  const Vec3 b = k * rho * q;
  const double x = a.squaredNorm() - b.squaredNorm();
  const double y = 2.0 * a.dot(b);
  const double theta = 0.5 * std::atan2(y, x);
  const double c = std::cos(theta);
  const double s = std::sin(theta);
  if (need) {
    const double rho3 = rho2 * rho;
    // v = c A + s B: dv = c dA + s dB + (c B - s A) dtheta, with
    // dtheta = (X (B^T dA + A^T dB) - Y (A^T dA - B^T dB)) / (X^2 + Y^2).
    const Vec3 dv_dtheta = c * b - s * a;
    const double norm = x * x + y * y;
    auto chain = [&](const Mat3& ja, const Mat3& jb) {
      const Eigen::RowVector3d dtheta =
          (x * (b.transpose() * ja + a.transpose() * jb) - y * (a.transpose() * ja - b.transpose() * jb)) / norm;
      return Mat3(c * ja + s * jb + dv_dtheta * dtheta);
    };
    if (J_r != nullptr) {
      // The radiation term kappa (m / rho - r (r.m) / rho^3) and the induction term k rho Q.
      Mat3 jrad = -(m * r.transpose()) - r * m.transpose() + (3.0 * rm / rho2) * (r * r.transpose());
      jrad.diagonal().array() -= rm;
      const Mat3 ja = jq_r + (kappa / rho3) * jrad;
      const Mat3 jb = k * ((q * r.transpose()) / rho + rho * jq_r);
      *J_r = chain(ja, jb);
    }
    if (J_m != nullptr) {
      Mat3 jrad = -(r * r.transpose()) / rho3;
      jrad.diagonal().array() += 1.0 / rho;
      *J_m = chain(jq_m + kappa * jrad, k * rho * jq_m);
    }
  }
  return c * a + s * b;
}

Vec3 DipoleField::moment_of_major_axis(const Vec3& r, const Vec3& h, double k, Mat3* J_m_r, Mat3* J_m_H) {
  if (k == 0.0) return moment(r, h, J_m_r, J_m_H);
  // v(m) - h is within (k r)^2 of linear in m: a few Newton steps reach machine precision.
  constexpr int kNewtonSteps = 4;
  Vec3 m = moment(r, h);
  Mat3 j_r, j_m;
  for (int i = 0; i < kNewtonSteps; ++i) {
    const Vec3 v = major_axis(r, m, k, nullptr, &j_m);
    m += j_m.lu().solve(h - v);
  }
  major_axis(r, m, k, &j_r, &j_m);
  const Mat3 j_m_inv = j_m.inverse();
  if (J_m_r != nullptr) *J_m_r = -j_m_inv * j_r;
  if (J_m_H != nullptr) *J_m_H = j_m_inv;
  return m;
}

MeasurementModel::MeasurementModel(const DispVec& d, double wavenumber)
    : t_(d.segment<3>(idx::kTrans)), k_(wavenumber) {
  const EulerTrig trig_d = EulerTrig::from_rpy(d.segment<3>(idx::kRot));
  r_d_ = trig_d.rotation();
  e_d_ = trig_d.rate_to_world();
}

Vec3 MeasurementModel::h(const StateVec& x, Jacobian<3, idx::kStateDim>* H_x,
                         Jacobian<3, idx::kDispDim>* H_d) const {
  const Vec3 p = x.segment<3>(idx::kPos);
  const Vec3 m = x.segment<3>(idx::kMom);
  const EulerTrig trig = EulerTrig::from_rpy(x.segment<3>(idx::kAtt));
  const Mat3 r_g = trig.rotation();
  const Mat3 r_kt = (r_g * r_d_).transpose();  // R_k^T, R_k = R(Psi) R(dPsi)
  const Vec3 rt = r_g * t_;
  const Vec3 r = rt - p;  // transmitter -> receiver in G_{k-1}
  Mat3 j_r, j_m;
  const bool need = H_x != nullptr || H_d != nullptr;
  const Vec3 field = DipoleField::major_axis(r, m, k_, need ? &j_r : nullptr, need ? &j_m : nullptr);
  if (need) {
    // A change dPsi rotates by omega = E_w(Psi) dPsi: d(R t) = -[R t]x omega moves r, and
    // the rotated frame adds R_k^T [H_G]x omega. dr/dp = -I, dr/dt = R(Psi).
    const Mat3 h_skew = skew(field);
    const Mat3 rkt_jr = r_kt * j_r;
    if (H_x != nullptr) {
      H_x->block<3, 3>(0, idx::kAtt) = r_kt * (h_skew - j_r * skew(rt)) * trig.rate_to_world();
      H_x->block<3, 3>(0, idx::kPos) = -rkt_jr;
      H_x->block<3, 3>(0, idx::kMom) = r_kt * j_m;
    }
    if (H_d != nullptr) {
      H_d->block<3, 3>(0, idx::kTrans) = rkt_jr * r_g;
      H_d->block<3, 3>(0, idx::kRot) = r_kt * h_skew * r_g * e_d_;
    }
  }
  return r_kt * field;
}

Vec3 MeasurementModel::h(const StateVec& x, const DispVec& d, Jacobian<3, idx::kStateDim>* H_x,
                         Jacobian<3, idx::kDispDim>* H_d, double wavenumber) {
  return MeasurementModel(d, wavenumber).h(x, H_x, H_d);
}

Vec3 MeasurementModel::h(const AugVec& xa, Jacobian<3, idx::kAugDim>* H, double wavenumber) {
  Jacobian<3, idx::kStateDim> h_x;
  Jacobian<3, idx::kDispDim> h_d;
  const Vec3 z = h(StateVec(xa.head<idx::kStateDim>()), DispVec(xa.tail<idx::kDispDim>()),
                   H != nullptr ? &h_x : nullptr, H != nullptr ? &h_d : nullptr, wavenumber);
  if (H != nullptr) *H << h_x, h_d;
  return z;
}

StateCov CompositionJacobians::F_x() const {
  StateCov f = StateCov::Identity();
  f.block<3, 3>(idx::kAtt, idx::kAtt) = att_att;
  f.block<3, 3>(idx::kPos, idx::kAtt) = pos_att;
  return f;
}

Jacobian<idx::kStateDim, idx::kDispDim> CompositionJacobians::F_d() const {
  Jacobian<idx::kStateDim, idx::kDispDim> f = Jacobian<idx::kStateDim, idx::kDispDim>::Zero();
  f.block<3, 3>(idx::kAtt, idx::kRot) = att_rot;
  f.block<3, 3>(idx::kPos, idx::kTrans) = pos_trans;
  return f;
}

StateVec CompositionModel::f(const StateVec& x, const DispVec& d, CompositionJacobians* J) {
  const EulerTrig trig = EulerTrig::from_rpy(x.segment<3>(idx::kAtt));
  const EulerTrig trig_d = EulerTrig::from_rpy(d.segment<3>(idx::kRot));
  const Mat3 r_g = trig.rotation();
  const Mat3 r_k = r_g * trig_d.rotation();
  const Vec3 rt = r_g * d.segment<3>(idx::kTrans);
  StateVec out;
  out.segment<3>(idx::kAtt) = rpy_from_rotation(r_k);                  // eq. (6)
  out.segment<3>(idx::kPos) = x.segment<3>(idx::kPos) - rt;            // eq. (7)
  out.segment<3>(idx::kMom) = x.segment<3>(idx::kMom);                 // eq. (8)
  if (J != nullptr) {
    // E_w(Psi_k)^-1 from R_k directly (no trigonometric call).
    const Mat3 e_inv_k = EulerTrig::from_rotation(r_k).world_to_rate();
    const Mat3 e_w = trig.rate_to_world();
    J->att_att = e_inv_k * e_w;
    J->pos_att = skew(rt) * e_w;
    J->att_rot = e_inv_k * r_g * trig_d.rate_to_world();
    J->pos_trans = -r_g;
  }
  return out;
}

void CompositionModel::compose_pose(Mat3& rotation, Vec3& p, const DispVec& d) {
  p -= rotation * d.segment<3>(idx::kTrans);                                  // eq. (7)
  rotation = rotation * EulerTrig::from_rpy(d.segment<3>(idx::kRot)).rotation();  // eq. (6)
}

StateVec CompositionModel::f(const StateVec& x, const DispVec& d, StateCov* F_x,
                             Jacobian<idx::kStateDim, idx::kDispDim>* F_d) {
  if (F_x == nullptr && F_d == nullptr) return f(x, d, static_cast<CompositionJacobians*>(nullptr));
  CompositionJacobians j;
  const StateVec out = f(x, d, &j);
  if (F_x != nullptr) *F_x = j.F_x();
  if (F_d != nullptr) *F_d = j.F_d();
  return out;
}

StateVec CompositionModel::f(const AugVec& xa, Jacobian<idx::kStateDim, idx::kAugDim>* F) {
  StateCov f_x;
  Jacobian<idx::kStateDim, idx::kDispDim> f_d;
  const StateVec out = f(StateVec(xa.head<idx::kStateDim>()), DispVec(xa.tail<idx::kDispDim>()),
                         F != nullptr ? &f_x : nullptr, F != nullptr ? &f_d : nullptr);
  if (F != nullptr) *F << f_x, f_d;
  return out;
}

DispVec compose_displacements(const DispVec& d1, const DispVec& d2, Mat6* J_d1, Mat6* J_d2) {
  const Vec3 a1 = d1.segment<3>(idx::kRot);
  const Vec3 a2 = d2.segment<3>(idx::kRot);
  const Mat3 r1 = rotation_from_rpy(a1);
  const Mat3 r12 = r1 * rotation_from_rpy(a2);
  const Vec3 a12 = rpy_from_rotation(r12);
  const Vec3 r1t2 = r1 * d2.segment<3>(idx::kTrans);
  DispVec out;
  out.segment<3>(idx::kTrans) = d1.segment<3>(idx::kTrans) + r1t2;
  out.segment<3>(idx::kRot) = a12;
  if (J_d1 != nullptr || J_d2 != nullptr) {
    const Mat3 e_inv = world_to_euler_rate(a12);
    if (J_d1 != nullptr) {
      const Mat3 e1 = euler_rate_to_world(a1);
      J_d1->setZero();
      J_d1->block<3, 3>(idx::kTrans, idx::kTrans) = Mat3::Identity();
      J_d1->block<3, 3>(idx::kTrans, idx::kRot) = -skew(r1t2) * e1;
      J_d1->block<3, 3>(idx::kRot, idx::kRot) = e_inv * e1;
    }
    if (J_d2 != nullptr) {
      J_d2->setZero();
      J_d2->block<3, 3>(idx::kTrans, idx::kTrans) = r1;
      J_d2->block<3, 3>(idx::kRot, idx::kRot) = e_inv * r1 * euler_rate_to_world(a2);
    }
  }
  return out;
}

}  // namespace sarloc::avalanche
