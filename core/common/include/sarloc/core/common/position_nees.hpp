#pragma once
// The NEES of a position estimate, one rule for the evaluations and their step traces.
//
//   const double nees = position_nees(estimate - truth, covariance);  // chi2_3 if consistent
#include "sarloc/core/common/types.hpp"

namespace sarloc {

/// err^T P^-1 err. A covariance that is not positive definite (a particle cloud collapsed onto
/// one point) claims certainty: infinite for any non-zero error, never negative or NaN.
double position_nees(const Vec3& error, const Mat3& covariance);

}  // namespace sarloc
