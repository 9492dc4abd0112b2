#include "sarloc/core/avalanche/moment_kalman.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "sarloc/core/avalanche/dipole_model.hpp"

namespace sarloc::avalanche {

Mat3 moment_gain(const Mat3& rotation, const Vec3& p) {
  Mat3 j_h_m;
  DipoleField::field(-p, Vec3::Zero(), nullptr, &j_h_m);
  return rotation.transpose() * j_h_m;
}

MomentUpdate update_moment(const Mat3& gain, Vec3& m, Mat3& M, const Vec3& z_valid, const Vec3& floor,
                           std::uint8_t axes, const FieldNoiseModel& noise) {
  MomentUpdate u;
  Vec3 h = gain * m;
  const Vec3 sigma = noise.sigma(h.norm(), floor);
  // An invalid axis is no observation: its row of C is zeroed and its variance set to 1, so its
  // innovation is 0 and S is block-diagonal (the same convention as the SOG filter).
  Mat3 c = gain;
  for (int a = 0; a < 3; ++a) {
    if ((axes & (1U << a)) != 0) continue;
    c.row(a).setZero();
    h[a] = 0.0;
  }
  const Mat3 mct = M * c.transpose();
  Mat3 s = c * mct;
  for (int a = 0; a < 3; ++a) s(a, a) += (axes & (1U << a)) != 0 ? sigma[a] * sigma[a] : 1.0;
  Mat3 s_inv;
  double det = 0.0;
  bool invertible = false;
  s.computeInverseAndDetWithCheck(s_inv, det, invertible, 0.0);  // S is tiny in (A/m)^2: no threshold
  if (!invertible || !(det > 0.0) || !std::isfinite(det)) return u;
  u.predicted = h;
  u.innovation_covariance = s;
  const double zeta = z_valid.dot(s_inv * h);
  const double sign = zeta >= 0.0 ? 1.0 : -1.0;
  const Vec3 nu = sign * z_valid - h;
  const Vec3 s_inv_nu = s_inv * nu;
  u.nis = nu.dot(s_inv_nu);
  // The other sign's term, exp(-2 |zeta|) relative to this one: below 1e-16 past 2 |zeta| = 37.
  u.ll = -0.5 * (u.nis + std::log(det));
  if (2.0 * std::fabs(zeta) < 37.0) u.ll += std::log1p(std::exp(-2.0 * std::fabs(zeta)));
  u.ok = true;
  if (M.isZero(0.0)) return u;  // a sampled moment: nothing to update
  const Mat3 k = mct * s_inv;
  m += k * nu;
  M -= k * mct.transpose();
  M = 0.5 * (M + M.transpose()).eval();
  return u;
}

void PredictiveMoments::add(double weight, const MomentUpdate& u) {
  if (!u.ok || !(weight > 0.0)) return;
  weight_ += weight;
  mean_ += weight * u.predicted;
  second_.noalias() += weight * (u.innovation_covariance + u.predicted * u.predicted.transpose());
}

double PredictiveMoments::nis(const Vec3& z_valid) const {
  if (!(weight_ > 0.0)) return 0.0;
  const Vec3 mean = mean_ / weight_;
  const Mat3 s = second_ / weight_ - mean * mean.transpose();
  const Eigen::LDLT<Mat3> ldlt(s);
  if (ldlt.info() != Eigen::Success) return std::numeric_limits<double>::max();
  const Vec3 plus = z_valid - mean, minus = -z_valid - mean;
  return std::min(plus.dot(ldlt.solve(plus)), minus.dot(ldlt.solve(minus)));
}

}  // namespace sarloc::avalanche
