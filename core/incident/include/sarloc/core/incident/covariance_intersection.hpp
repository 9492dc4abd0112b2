#pragma once
// Covariance intersection (CI): fuse estimates of the same quantity whose cross-correlations
// are unknown, without ever claiming more certainty than the data can support.
//
//   P^-1   = sum_i w_i P_i^-1,           sum_i w_i = 1, w_i >= 0
//   P^-1 x = sum_i w_i P_i^-1 x_i
// (Julier & Uhlmann 1997, eq. (4)-(5); N-source form in Niehsen 2002, eq. (2)).
//
// Why CI in sarloc-command. Estimates of one victim from different rescuers are correlated in
// ways nobody tracks: a rescuer republishes its filter's estimate at every step (successive
// estimates share all past data), rescuers close together see correlated GNSS errors (same
// satellites, same atmosphere), and a device and a daemon may both filter the same field
// samples. A Kalman/information-sum fusion treats them as independent and becomes
// overconfident (N copies of one estimate would give P/N), which in turn makes the association
// gates too tight and splits one victim into two. CI is consistent for ANY cross-correlation:
// if every P_i bounds its own error (P_i >= E[e_i e_i^T]) then P bounds the fused error
// (Julier & Uhlmann 1997, Theorem 1). The price is conservatism: independent sources do not
// shrink P below the best single source; the fused MEAN still averages them.
//
// Weights:
//   kInverseTrace (default): the fast, non-iterative weights w_i = (1/tr P_i) / sum_j (1/tr P_j)
//     (Niehsen 2002, eq. (10); Franken & Huepper 2005). Any N, no optimisation, deterministic;
//     identical covariances give the plain average, which is the best mean when the sources are
//     alike. Near-optimal in trace for the near-isotropic horizontal covariances that GNSS-
//     dominated victim estimates have.
//   kMinTrace: w minimising tr(P) exactly for N = 2 (golden-section search over w in [0, 1],
//     tr(P(w)) is convex: Julier & Uhlmann 1997, section 4); for N > 2 the sources are fused
//     pairwise in order of increasing trace, each pair with its optimal w (sequential CI is
//     still consistent, but depends on the order).
//
//   std::vector<GaussianPosition> in = {a, b, c};
//   CiResult r = covariance_intersection(in);          // r.fused, r.weights
#include <vector>

#include "sarloc/core/common/types.hpp"

namespace sarloc::incident {

enum class CiWeighting : std::uint8_t { kInverseTrace = 0, kMinTrace = 1 };

struct CiResult {
  GaussianPosition fused;
  std::vector<double> weights;  ///< one per input (kMinTrace, N > 2: effective weights)
};

/// Fuses N >= 1 estimates. Throws InputError when inputs is empty, an entry is not finite or a
/// covariance is not symmetric positive definite.
CiResult covariance_intersection(const std::vector<GaussianPosition>& inputs,
                                 CiWeighting weighting = CiWeighting::kInverseTrace);

}  // namespace sarloc::incident
