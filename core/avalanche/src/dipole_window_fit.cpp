#include "sarloc/core/avalanche/dipole_window_fit.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <utility>

#include "sarloc/core/avalanche/dipole_model.hpp"

namespace sarloc::avalanche {

namespace {

// Closer than this to the dipole the point-dipole model means nothing: a fit stepping there is
// refused, not evaluated.
constexpr double kMinRange = 0.05;

}  // namespace

// The window's normal equations on [p; m], each valid axis of each sample normalised by its
// sigma: J^T J, J^T e and the sum of squares e^T e (no per-row storage: a fit makes dozens).
struct DipoleWindowFit::Normalised {
  Mat6 jtj = Mat6::Zero();
  Vec6 jte = Vec6::Zero();
  double deviance = 0.0;
};

DipoleWindowFit::DipoleWindowFit(const DipoleFitModel& model, std::vector<WindowSample> samples, const Vec3& reference)
    : model_(model), samples_(std::move(samples)) {
  sigma_.reserve(samples_.size());
  for (const WindowSample& s : samples_) {
    const Vec3 z = s.field.cwiseProduct(Vec3((s.axes & 1U) != 0, (s.axes & 2U) != 0, (s.axes & 4U) != 0));
    // The filter's noise, its calibration errors as white noise, and the antenna's position
    // error times the field's gradient (|dH/dr| is about 3 |H| / r).
    const Vec3 base = model_.noise.sigma(z.norm(), model_.noise.floor(s.floor));  // never a zero sigma
    const double gradient = 3.0 * z.norm() / std::max(kMinRange, (s.antenna - reference).norm());
    Vec3 sigma;
    for (int a = 0; a < 3; ++a) {
      const Vec3 var_e = model_.calibration_variance.segment<3>(3 * a);
      sigma[a] = std::sqrt(base[a] * base[a] + var_e.dot(z.cwiseAbs2()) + gradient * gradient * s.position_variance);
    }
    sigma_.push_back(sigma);
    for (int a = 0; a < 3; ++a) rows_ += (s.axes >> a) & 1U;
  }
}

std::optional<DipoleWindowFit::Normalised> DipoleWindowFit::normalise(const Vec3& p, const Vec3& m) const {
  if (rows_ == 0) return std::nullopt;
  Normalised n;
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    const WindowSample& s = samples_[i];
    if ((s.axes & 0b111U) == 0) continue;
    const Vec3 r = s.antenna - p;  // transmitter -> receiver
    if (!(r.norm() >= kMinRange)) return std::nullopt;
    Mat3 j_r;
    Mat3 j_m;
    const Vec3 field_g = DipoleField::major_axis(r, m, model_.wavenumber, &j_r, &j_m);
    const Vec3 h = s.rotation.transpose() * field_g;
    const Mat3 h_p = -s.rotation.transpose() * j_r;
    const Mat3 h_m = s.rotation.transpose() * j_m;
    // A receiver measures +-h: the sign that explains the sample best.
    double zeta = 0.0;
    for (int a = 0; a < 3; ++a)
      if ((s.axes & (1U << a)) != 0) zeta += s.field[a] * h[a] / (sigma_[i][a] * sigma_[i][a]);
    const double sign = zeta >= 0.0 ? 1.0 : -1.0;
    for (int a = 0; a < 3; ++a) {
      if ((s.axes & (1U << a)) == 0) continue;
      const double sd = sigma_[i][a];
      const double e = (sign * s.field[a] - h[a]) / sd;
      Vec6 j;
      j << h_p.row(a).transpose() / sd, h_m.row(a).transpose() / sd;
      n.jtj.selfadjointView<Eigen::Lower>().rankUpdate(j);
      n.jte += j * e;
      n.deviance += e * e;
    }
  }
  n.jtj = n.jtj.selfadjointView<Eigen::Lower>();
  if (!std::isfinite(n.deviance)) return std::nullopt;
  return n;
}

std::optional<double> DipoleWindowFit::deviance(const Vec3& p, const Vec3& m) const {
  const auto n = normalise(p, m);
  if (!n) return std::nullopt;
  return n->deviance;
}

std::optional<DipoleFit> DipoleWindowFit::fit(const Vec3& p0, const Vec3& m0) const { return solve(p0, m0, true); }

std::optional<DipoleFit> DipoleWindowFit::fit_moment(const Vec3& p0, const Vec3& m0) const {
  return solve(p0, m0, false);
}

std::optional<DipoleFit> DipoleWindowFit::solve(const Vec3& p0, const Vec3& m0, bool position_free) const {
  Vec3 p = p0;
  Vec3 m = m0;
  auto current = normalise(p, m);
  if (!current) return std::nullopt;
  const int first = position_free ? 0 : 3;  // the free columns of [p; m]
  const int free = 6 - first;
  double lambda = 1e-3;
  for (int it = 0; it < model_.max_iterations; ++it) {
    // Levenberg-Marquardt with Marquardt's scaling: p (m) and m (A m^2) differ in scale.
    const Eigen::MatrixXd jtj = current->jtj.bottomRightCorner(free, free);
    const Eigen::VectorXd jte = current->jte.tail(free);
    bool accepted = false;
    double gain = 0.0;
    while (lambda < 1e8) {
      Eigen::MatrixXd a = jtj;
      a.diagonal() += lambda * jtj.diagonal().cwiseMax(1e-12);
      const Eigen::VectorXd step = a.ldlt().solve(jte);
      Vec3 p_try = p;
      Vec3 m_try = m;
      if (position_free) p_try += step.head<3>();
      m_try += step.tail<3>();
      const auto tried = normalise(p_try, m_try);
      if (tried && tried->deviance < current->deviance) {
        gain = current->deviance - tried->deviance;
        p = p_try;
        m = m_try;
        current = tried;
        lambda = std::max(1e-9, lambda * 0.3);
        accepted = true;
        break;
      }
      lambda *= 10.0;
    }
    // No step lowers the deviance, or a Gauss-Newton-sized step (lambda small) lowered it by
    // nothing that matters: a minimum. A tiny gain under a large lambda is a short step in a flat
    // valley (a deep victim), not the bottom of it.
    if (!accepted || (gain < 1e-6 * std::max(1.0, current->deviance) && lambda < 1e-2)) break;
  }
  DipoleFit out;
  out.position = p;
  out.moment = m;
  out.deviance = current->deviance;
  out.valid_axes = rows_;
  const Eigen::MatrixXd info = current->jtj.bottomRightCorner(free, free);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(info);
  out.covariance = Mat6::Zero();
  if (ldlt.info() == Eigen::Success && ldlt.isPositive())
    out.covariance.bottomRightCorner(free, free) = ldlt.solve(Eigen::MatrixXd::Identity(free, free));
  else
    out.covariance.bottomRightCorner(free, free) = Eigen::MatrixXd::Identity(free, free) * 1e6;
  return out;
}

}  // namespace sarloc::avalanche
