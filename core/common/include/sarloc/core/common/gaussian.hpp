#pragma once
// Gaussian helpers shared by the avalanche filter, the search controller and the incident
// fusion (Eigen and the standard library only, so core/avalanche and core/incident can both
// use them without depending on each other). One implementation of each:
//   - the 95 % radius of a position covariance along its worst axis (located / converged tests);
//   - log Phi(u), the log standard-normal CDF, accurate far in the lower tail (the SOG
//     filter's surface term P(p_z below the snow));
//   - moment matching of weighted Gaussians (seed 000, eq. (18): mixture mean and covariance,
//     also the merge of near-duplicate components).
//
//   double r = radius95_3d(estimate.relative.covariance);   // m
//   GaussianMoments<9> mm = match_moments<9>(n, [&](std::size_t k) {
//     return WeightedGaussianRef<9>{log_w[k], x[k], P[k]};
//   });
#include <cmath>
#include <cstddef>
#include <vector>

#include "sarloc/core/common/types.hpp"

namespace sarloc {

/// chi2_3(0.95), chi2_2(0.95) = -2 ln 0.05, chi2_2(0.99) = -2 ln 0.01 and chi2_2(0.999) = -2 ln
/// 0.001 (to double precision; gaussian_test checks them).
inline constexpr double kChi2_3_95 = 7.814727903251178;
inline constexpr double kChi2_2_95 = 5.991464547107979;
inline constexpr double kChi2_2_99 = 9.210340371976184;
inline constexpr double kChi2_2_999 = 13.815510557964274;

/// 95 % radius (m) of a 3-D position covariance along its worst axis:
/// sqrt(chi2_3(0.95) lambda_max). A negative lambda_max (round-off) counts as 0.
double radius95_3d(const Mat3& covariance);

/// 95 % radius (m) of the horizontal (x, y) marginal of a 3-D position covariance along its
/// worst axis: sqrt(chi2_2(0.95) lambda_max of the top-left 2x2 block).
double radius95_2d(const Mat3& covariance);

/// The 95 % ellipse of a horizontal (x, y) covariance C, {d : d^T C^-1 d <= chi2_2(0.95)}:
/// semi-axes sqrt(chi2_2(0.95) lambda) (a negative lambda, round-off, counts as 0) and the major
/// axis's angle from x (east), counter-clockwise. Drawn on the report's map, exported as GeoJSON.
struct Ellipse95 {
  double semi_major_m = 0.0;
  double semi_minor_m = 0.0;
  double major_angle_rad = 0.0;
};
Ellipse95 ellipse95(const Eigen::Matrix2d& covariance);
/// `points` (>= 3) points on the ellipse about `centre`, counter-clockwise, not closed.
std::vector<Eigen::Vector2d> ellipse95_outline(const Eigen::Vector2d& centre, const Eigen::Matrix2d& covariance,
                                               int points = 36);

/// log Phi(u), Phi the standard-normal CDF: log(erfc(-u / sqrt 2) / 2), and below u = -30
/// (where erfc underflows) its asymptote -u^2/2 - log(-u sqrt(2 pi)).
double log_normal_cdf(double u);

/// One member of a moment match: its log weight, its mean (already expressed in the
/// coordinates to average in, e.g. angles relative to a reference) and its covariance.
template <int N>
struct WeightedGaussianRef {
  double log_weight;
  Eigen::Matrix<double, N, 1> mean;
  const Eigen::Matrix<double, N, N>& covariance;
};

template <int N>
struct GaussianMoments {
  Eigen::Matrix<double, N, 1> mean = Eigen::Matrix<double, N, 1>::Zero();
  Eigen::Matrix<double, N, N> covariance = Eigen::Matrix<double, N, N>::Zero();
  double weight_sum = 0.0;  ///< sum of w_k = exp(log_weight_k - log_base)
};

/// Moment matching (seed 000, eq. (18)) of members k = 0 .. n-1, in that order:
///   w_k = exp(log_weight_k - log_base),  W = sum w_k,
///   mean = sum w_k x_k / W,  covariance = sum w_k (P_k + (x_k - mean)(x_k - mean)^T) / W.
/// `member(k)` returns a WeightedGaussianRef<N>; it is called twice per member (mean pass,
/// covariance pass) and must return the same both times. log_base (e.g. the largest log
/// weight) keeps the exponentials in range; the merged log weight is log_base + log(W).
/// n must be > 0.
template <int N, typename Member>
GaussianMoments<N> match_moments(std::size_t n, Member&& member, double log_base = 0.0) {
  GaussianMoments<N> out;
  for (std::size_t k = 0; k < n; ++k) {
    const WeightedGaussianRef<N> g = member(k);
    const double w = std::exp(g.log_weight - log_base);
    out.weight_sum += w;
    out.mean += w * g.mean;
  }
  out.mean /= out.weight_sum;
  for (std::size_t k = 0; k < n; ++k) {
    const WeightedGaussianRef<N> g = member(k);
    const double w = std::exp(g.log_weight - log_base);
    const Eigen::Matrix<double, N, 1> dv = g.mean - out.mean;
    out.covariance += w * (g.covariance + dv * dv.transpose());
  }
  out.covariance /= out.weight_sum;
  return out;
}

}  // namespace sarloc
