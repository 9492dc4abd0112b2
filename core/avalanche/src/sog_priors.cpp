// The SOG filter's priors (burial depth, moment) and its negative information (a pulse due
// and not heard).
#include "sarloc/core/avalanche/sog_filter.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "sarloc/core/avalanche/rotation.hpp"

#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {
using namespace sog_detail;  // the shared private helpers (sog_filter_detail.hpp)


double SogFilter::apply_miss(const Vec3& floor) {
  // Move every Gaussian, and the place the signal was last heard, to where the rescuer stands
  // now (composition, no correction).
  const Displacement disp = odometry_.take();
  const MixtureMoments before = moments();
  heard_at_ = moved_point(before, heard_at_, disp.mean);
  move_anchor(disp);
  move_window(before, disp);
  for (auto& c : components_) {
    CompositionJacobians f;
    const StateVec x = CompositionModel::f(c.x, disp.mean, &f);
    c.P = composed_covariance(c.P, f, disp.covariance);
    c.P = 0.5 * (c.P + c.P.transpose()).eval();
    c.calibration_cross = composed_cross(c.calibration_cross, f);
    c.x = x;
  }
  // P(not detected | Gaussian): averaged over its sigma points in position and moment (kappa = 0,
  // 2n equal weights). One wide Gaussian spans ranges whose fields differ by orders of magnitude;
  // its mean alone would make it all heard or all unheard.
  const MeasurementModel here(DispVec::Zero(), config_.wavenumber());
  const Vec3 weight = floor.cwiseAbs2().cwiseInverse() * config_.miss_power_margin;
  auto p_miss = [&](const StateVec& x) {
    const Vec3 h = here.h(x);
    return 1.0 - detection_.probability(h.cwiseAbs2().dot(weight));
  };
  constexpr int kDim = 6;  // p and m, adjacent in the state
  static_assert(idx::kMom == idx::kPos + 3);
  double max_log_weight = -std::numeric_limits<double>::infinity();
  for (const auto& c : components_) max_log_weight = std::max(max_log_weight, c.log_weight);
  double evidence = 0.0;  // P(not detected | everything so far), relative to the heaviest Gaussian
  for (auto& c : components_) {
    const Eigen::LLT<Eigen::Matrix<double, kDim, kDim>> llt(c.P.block<kDim, kDim>(idx::kPos, idx::kPos));
    double p = 0.0;
    if (llt.info() != Eigen::Success) {
      p = p_miss(c.x);  // no spread to average over: its mean
    } else {
      const Eigen::Matrix<double, kDim, kDim> spread = std::sqrt(static_cast<double>(kDim)) * llt.matrixL().toDenseMatrix();
      for (int j = 0; j < kDim; ++j) {
        for (double side : {-1.0, 1.0}) {
          StateVec x = c.x;
          x.segment<kDim>(idx::kPos) += side * spread.col(j);
          p += p_miss(x);
        }
      }
      p /= 2.0 * kDim;
    }
    evidence += std::exp(c.log_weight - max_log_weight) * p;
    c.log_weight += std::log(std::max(p, config_.miss_weight_floor));
  }
  normalise_and_prune();
  return std::log(std::max(evidence, std::numeric_limits<double>::min())) + max_log_weight;
}

double SogFilter::prior_log_support(const SogComponent& c) const {
  double support = 0.0;
  if (config_.surface_constraint) {
    // log P(p_z <= surface) = log Phi((surface - mu_z) / sigma_z), surface = -antenna height.
    const double mu = c.x[idx::kPos + 2];
    const double sd = std::sqrt(c.P(idx::kPos + 2, idx::kPos + 2));
    support += log_normal_cdf((-config_.antenna_height_m - mu) / sd);
  }
  if (config_.moment_constraint) {
    // log P(lo <= |m| <= hi), |m| ~ N(|m_hat|, u' P_mm u), u = m_hat / |m_hat|; computed from
    // the nearer bound's tail so that it stays finite far outside.
    const Vec3 m = c.x.segment<3>(idx::kMom);
    const double mu = m.norm();
    if (mu > 0.0) {
      const Vec3 u = m / mu;
      const double sd = std::sqrt(std::max(u.dot(c.P.block<3, 3>(idx::kMom, idx::kMom) * u), 1e-30));
      const double a = (config_.standard.moment_min() * (1.0 - config_.moment_margin) - mu) / sd;
      const double b = (config_.standard.moment_max() * (1.0 + config_.moment_margin) - mu) / sd;
      // P = Phi(b) - Phi(a) = Phi(-a) - Phi(-b).
      const double near = a > -b ? log_normal_cdf(-a) : log_normal_cdf(b);
      const double far = a > -b ? log_normal_cdf(-b) : log_normal_cdf(a);
      support += near + std::log1p(-std::min(std::exp(far - near), 1.0 - 1e-16));
    }
  }
  return support;
}

void SogFilter::apply_priors() {
  if (!config_.surface_constraint && !config_.moment_constraint) return;
  for (auto& c : components_) {
    const double log_phi = prior_log_support(c);
    c.log_weight += log_phi - c.log_support;
    c.log_support = log_phi;
  }
}

}  // namespace sarloc::avalanche
