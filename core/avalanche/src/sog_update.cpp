// The SOG filter's measurement update: EKF or iterated EKF per component, sign-invariant
// likelihood, the optional attitude reading.
#include "sarloc/core/avalanche/sog_filter.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {
using namespace sog_detail;  // the shared private helpers (sog_filter_detail.hpp)


namespace {

// Linear Kalman update of Psi with an attitude-sensor reading (H = [I 0 0]); returns the
// log-likelihood of the reading (eq. (17) for this extra observation).
double orientation_update(SogComponent& c, const OrientationObservation& o) {
  Vec3 nu = o.rpy - c.x.segment<3>(idx::kAtt);
  for (int k = 0; k < 3; ++k) nu[k] = wrap_angle(nu[k]);
  const Mat3 s = c.P.block<3, 3>(idx::kAtt, idx::kAtt) + o.covariance;
  const Mat3 s_inv = s.inverse();
  const Jacobian<idx::kStateDim, 3> pht = c.P.middleCols<3>(idx::kAtt);
  const Jacobian<idx::kStateDim, 3> k = pht.lazyProduct(s_inv);
  c.x += k * nu;
  c.P.noalias() -= k.lazyProduct(pht.transpose());
  // The reading does not depend on the calibration: E's part of Psi's error is corrected with it.
  const Eigen::Matrix<double, 3, kCalibrationDim> psi_cross = c.calibration_cross.middleRows<3>(idx::kAtt);
  c.calibration_cross.noalias() -= k.lazyProduct(psi_cross);
  c.P = 0.5 * (c.P + c.P.transpose()).eval();
  c.x[idx::kAtt + 2] = wrap_angle(c.x[idx::kAtt + 2]);
  return -0.5 * (nu.dot(s_inv * nu) + std::log(s.determinant()));
}

// The estimation step of eq. (14) for one component on x* = [x; d], P* = blkdiag(P, Q), with the
// sign-invariant likelihood: what the update and the predictive likelihood share.
struct Innovation {
  Jacobian<idx::kStateDim, 3> pht;  ///< Cov(x, z): P H_x^T + C H_E^T
  Jacobian<idx::kDispDim, 3> qht;
  Eigen::Matrix<double, 3, kCalibrationDim> cal;  ///< Cov(z, E): H_x C + H_E Sigma_E
  Mat3 s_inv;
  Vec3 s_inv_nu;
  double sign = 1.0; ///< the sign of z that explains it best
  double nis = 0.0;  ///< the better sign's NIS
  double ll = 0.0;   ///< log p(z | component), common constants dropped
};

// h and its Jacobians at (x, d) with the invalid axes' rows zeroed, and the per-axis noise.
struct Linearisation {
  Vec3 h;
  Jacobian<3, idx::kStateDim> h_x;
  Jacobian<3, idx::kDispDim> h_d;
  Jacobian<3, kCalibrationDim> h_e;  ///< dz/dE of z = (I + E) h: row a holds h in E(a, .)'s columns
  Vec3 sigma;
};

// What the update needs of the calibration's consider parameters: their variances (null when the
// receiver is stated free of calibration error: no cross-covariance arises).
using CalibrationPrior = const CalibrationVec*;

Linearisation linearise(const StateVec& x, const MeasurementModel& measurement, const Vec3& floor, std::uint8_t axes,
                        const FieldNoiseModel& noise) {
  Linearisation l;
  l.h = measurement.h(x, &l.h_x, &l.h_d);
  l.sigma = noise.sigma(l.h.norm(), floor);
  l.h_e = calibration_jacobian(l.h);
  // An invalid axis is no observation: its rows of h, H_x and H_d are zeroed and its
  // innovation variance set to 1, so S is block-diagonal, the axis's innovation is 0 and
  // the update, the NIS and the weights (up to a constant) are those of the valid axes.
  for (int a = 0; a < 3; ++a) {
    if ((axes & (1U << a)) != 0) continue;
    l.h[a] = 0.0;
    l.h_x.row(a).setZero();
    l.h_d.row(a).setZero();
    l.h_e.row(a).setZero();
  }
  return l;
}

// S = H_x P H_x^T + H_d Q H_d^T + R and the gains' P H^T, Q H^T; false if S is not positive.
// With calibration errors E (Schmidt-Kalman): S gains H_x C H_E^T + H_E C^T H_x^T + H_E Sigma_E
// H_E^T and P H^T gains C H_E^T, C = Cov(x, E) of the component.
bool innovation_covariance(const Linearisation& l, const SogComponent& c, CalibrationPrior calibration,
                           const DispCov& q, std::uint8_t axes, Innovation& in, double& det) {
  in.pht = c.P.lazyProduct(l.h_x.transpose());
  in.qht = q.lazyProduct(l.h_d.transpose());
  Mat3 s = l.h_x * in.pht + l.h_d * in.qht;
  if (calibration != nullptr) {
    // H_E is sparse: its row a holds h in E(a, .)'s three columns and nothing else
    // (calibration_jacobian), so each product with it takes 3 of the 9 columns and
    // H_E Sigma_E H_E^T is diagonal.
    Jacobian<idx::kStateDim, 3> cht;
    in.cal.noalias() = l.h_x.lazyProduct(c.calibration_cross);
    for (int a = 0; a < 3; ++a) {
      const Vec3 h_a = l.h_e.block<1, 3>(a, 3 * a).transpose();
      const Vec3 var_h_a = calibration->segment<3>(3 * a).cwiseProduct(h_a);
      cht.col(a).noalias() = c.calibration_cross.middleCols<3>(3 * a) * h_a;
      in.cal.block<1, 3>(a, 3 * a) += var_h_a.transpose();
      s(a, a) += h_a.dot(var_h_a);
    }
    const Mat3 hx_cht = l.h_x * cht;
    s += hx_cht + hx_cht.transpose();
    in.pht += cht;
  } else {
    in.cal.setZero();
  }
  for (int a = 0; a < 3; ++a) s(a, a) += (axes & (1U << a)) != 0 ? l.sigma[a] * l.sigma[a] : 1.0;
  det = s.determinant();
  if (!(det > 0.0) || !std::isfinite(det)) return false;
  in.s_inv = s.inverse();
  return true;
}

// The innovation of component c linearised at its mean (l = linearise(c.x, ...)).
std::optional<Innovation> innovate(const SogComponent& c, const Linearisation& l, const Vec3& z_valid,
                                   std::uint8_t axes, CalibrationPrior calibration, const DispCov& q) {
  Innovation in;
  double det = 0.0;
  if (!innovation_covariance(l, c, calibration, q, axes, in, det)) return std::nullopt;
  // Sign-invariant likelihood: the receiver measures +-h, p(z) = (N(z; h, S) + N(-z; h, S)) / 2.
  // The component is updated with the sign that explains z best (zeta = z^T S^-1 h decides:
  // NIS(+-) = z^T S^-1 z + h^T S^-1 h -+ 2 zeta); its weight takes both terms.
  const double zeta = z_valid.dot(in.s_inv * l.h);
  in.sign = zeta >= 0.0 ? 1.0 : -1.0;
  const Vec3 nu = in.sign * z_valid - l.h;
  in.s_inv_nu = in.s_inv * nu;
  in.nis = nu.dot(in.s_inv_nu);
  const double nis_other = in.nis + 4.0 * std::fabs(zeta);
  // eq. (17) in log space (the common -1.5 log(2 pi) and log 1/2 are dropped).
  in.ll = -0.5 * (in.nis + std::log(det)) + std::log1p(std::exp(-0.5 * (nis_other - in.nis)));
  return in;
}

// Iterated EKF (Gauss-Newton on the augmented state [x; d]): re-linearise at the updated state
// while the field there differs from the linear prediction by more than threshold_sigmas.
// x_{i+1} = x0 + P H_i^T S_i^-1 (z - h(x_i) - H_i (x0 - x_i)); the returned gains and S^-1
// are those of the last linearisation (the posterior covariance uses them), nis and ll stay
// the prior-linearised ones (the component's weight is the predictive likelihood).
Innovation iterate(const SogComponent& c, const Linearisation& at_prior, const Innovation& first, const Vec3& z_valid,
                   const Vec3& floor, std::uint8_t axes, CalibrationPrior calibration, const DispVec& d0,
                   const DispCov& q, const FieldNoiseModel& noise, double wavenumber, std::uint32_t max_iterations,
                   double threshold_sigmas) {
  Innovation in = first;
  const Vec3 z = in.sign * z_valid;
  StateVec x_i = c.x + in.pht * in.s_inv_nu;
  DispVec d_i = d0 + in.qht * in.s_inv_nu;
  Linearisation l_prev = at_prior;
  StateVec x_prev = c.x;
  DispVec d_prev = d0;
  for (std::uint32_t it = 0; it < max_iterations; ++it) {
    const Linearisation l = linearise(x_i, MeasurementModel(d_i, wavenumber), floor, axes, noise);
    // How far the field at x_i is from what the last linearisation predicted there.
    const Vec3 linear = l_prev.h + l_prev.h_x * (x_i - x_prev) + l_prev.h_d * (d_i - d_prev);
    const Vec3 gap = (l.h - linear).cwiseQuotient(l.sigma);
    if (gap.squaredNorm() <= threshold_sigmas * threshold_sigmas) break;
    Innovation next = in;
    double det = 0.0;
    if (!innovation_covariance(l, c, calibration, q, axes, next, det)) break;
    const Vec3 nu = z - l.h - l.h_x * (c.x - x_i) - l.h_d * (d0 - d_i);
    next.s_inv_nu = next.s_inv * nu;
    const StateVec x_next = c.x + next.pht * next.s_inv_nu;
    const DispVec d_next = d0 + next.qht * next.s_inv_nu;
    if (!x_next.allFinite() || !d_next.allFinite()) break;
    in = next;
    l_prev = l;
    x_prev = x_i;
    d_prev = d_i;
    x_i = x_next;
    d_i = d_next;
  }
  return in;
}

}  // namespace

std::optional<FieldFit> SogFilter::predictive_fit(const Vec3& field, const Vec3& noise, std::uint8_t axes) const {
  if (components_.empty() || axes == 0 || axes > kAllAxes || !field.allFinite() || !noise.allFinite())
    return std::nullopt;
  const Displacement disp = odometry_.pending_displacement();
  const MeasurementModel measurement(disp.mean, config_.wavenumber());
  const Vec3 floor = config_.noise().floor(noise);
  const Vec3 z_valid = valid_axes_only(field, axes);
  const CalibrationVec calibration_variance = config_.calibration_variance();
  const CalibrationPrior calibration = calibration_variance.any() ? &calibration_variance : nullptr;
  // log sum_i w_i p(z | i), accumulated stably; the log weights are normalised (every update
  // ends in normalise_and_prune, merging keeps the sum).
  double max_term = -std::numeric_limits<double>::infinity();
  double sum = 0.0;
  double min_nis = std::numeric_limits<double>::infinity();
  for (const SogComponent& c : components_) {
    const auto in = innovate(c, linearise(c.x, measurement, floor, axes, config_.noise()), z_valid, axes, calibration,
                             disp.covariance);
    if (!in) continue;
    min_nis = std::min(min_nis, in->nis);
    const double term = c.log_weight + in->ll;
    if (term > max_term) {
      sum = sum * std::exp(max_term - term) + 1.0;
      max_term = term;
    } else {
      sum += std::exp(term - max_term);
    }
  }
  if (sum == 0.0) return std::nullopt;
  return FieldFit{max_term + std::log(sum), min_nis};
}

void SogFilter::update_field(const Vec3& z, const Vec3& floor, std::uint8_t axes,
                             const Displacement& disp, const OrientationObservation* orientation,
                             SogStepResult& result) {
  const DispCov& q = disp.covariance;
  // h of eq. (14) linearised at the odometry mean: R(dPsi), E_w(dPsi) shared by every component.
  const MeasurementModel measurement(disp.mean, config_.wavenumber());
  const FieldNoiseModel noise = config_.noise();
  const Vec3 z_valid = valid_axes_only(z, axes);
  const CalibrationVec calibration_variance = config_.calibration_variance();
  const CalibrationPrior calibration = calibration_variance.any() ? &calibration_variance : nullptr;
  double max_ll = -std::numeric_limits<double>::infinity();
  double min_nis = std::numeric_limits<double>::infinity();

  std::size_t out = 0;
  for (std::size_t i = 0; i < components_.size(); ++i) {
    SogComponent& c = components_[i];
    const StateCov& p = c.P;
    const Linearisation at_prior = linearise(c.x, measurement, floor, axes, noise);
    const auto innovation = innovate(c, at_prior, z_valid, axes, calibration, q);
    if (!innovation) {
      ++result.dropped_numerical;
      continue;
    }
    const Innovation updated =
        config_.iterated_update_max > 0
            ? iterate(c, at_prior, *innovation, z_valid, floor, axes, calibration, disp.mean, q, noise,
                      config_.wavenumber(), config_.iterated_update_max, config_.relinearise_threshold_sigmas)
            : *innovation;
    const auto& [pht, qht, cal, s_inv, s_inv_nu, sign, nis, ll] = updated;
    min_nis = std::min(min_nis, nis);
    const StateVec x_post = c.x + pht * s_inv_nu;
    const DispVec d_post = disp.mean + qht * s_inv_nu;

    // --- Composition step (eq. (9), (15)) evaluated at the posterior ---
    // F_x = [[A,0,0],[C,I,0],[0,0,I]], F_d = [[0,D],[T,0],[0,0]] (CompositionJacobians).
    CompositionJacobians f;
    const StateVec x_new = CompositionModel::f(x_post, d_post, &f);

    StateCov p_new = composed_covariance(p, f, q);
    // M = F_x P H_x^T + F_d Q H_d^T.
    Jacobian<idx::kStateDim, 3> mm = pht;
    mm.middleRows<3>(idx::kAtt) = f.att_att * pht.middleRows<3>(idx::kAtt) +
                                  f.att_rot * qht.middleRows<3>(idx::kRot);
    mm.middleRows<3>(idx::kPos) += f.pos_att * pht.middleRows<3>(idx::kAtt) +
                                   f.pos_trans * qht.middleRows<3>(idx::kTrans);
    const Jacobian<idx::kStateDim, 3> mm_s = mm.lazyProduct(s_inv);
    p_new.noalias() -= mm_s.lazyProduct(mm.transpose());
    p_new = 0.5 * (p_new + p_new.transpose()).eval();

    if (!p_new.allFinite() || !(p_new.diagonal().minCoeff() > 0.0) || !x_post.allFinite()) {
      ++result.dropped_numerical;
      continue;
    }
    // C_k = F_x C - M S^-1 Cov(z, E): x and d corrected with the calibration's share of z.
    CalibrationCross cross_new = CalibrationCross::Zero();
    if (calibration != nullptr) cross_new = composed_cross(c.calibration_cross, f) - mm_s.lazyProduct(cal);
    SogComponent& dst = components_[out++];
    dst.x = x_new;
    dst.P = p_new;
    dst.calibration_cross = cross_new;
    dst.log_weight = c.log_weight + ll;
    max_ll = std::max(max_ll, ll);
    // Optional attitude-sensor update on the composed state (same component, still in cache).
    if (orientation != nullptr) dst.log_weight += orientation_update(dst, *orientation);
  }
  components_.resize(out);
  result.log_likelihood = max_ll;
  result.min_nis = min_nis;
  if (components_.empty())
    throw InputError("field_measurement.field = " + vec_text(z) +
                     ": every hypothesis became numerically invalid");
}

}  // namespace sarloc::avalanche
