#pragma once
// Chi-square distribution without Boost: CDF through the regularised lower incomplete gamma
// function (series / continued fraction, Numerical Recipes 6.2) and the quantile by safeguarded
// Newton iteration. Used for NEES bounds (seed 001, "Consistency testing") and 95 % radii.
//
//   double upper = chi_square_quantile(0.975, 3 * n) / n;   // bound on the mean NEES of n runs
namespace sarloc {

/// P(X <= x) for X ~ chi2(dof). dof > 0, x >= 0, otherwise throws InputError.
double chi_square_cdf(double x, double dof);

/// x such that chi_square_cdf(x, dof) = p, p in (0, 1), dof > 0 (throws InputError otherwise).
double chi_square_quantile(double p, double dof);

}  // namespace sarloc
