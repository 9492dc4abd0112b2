#include "sarloc/core/common/chi_square.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "sarloc/core/common/errors.hpp"

namespace sarloc {
namespace {

// Regularised lower incomplete gamma P(a, x).
double gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double gln = std::lgamma(a);
  if (x < a + 1.0) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 10000; ++n) {
      ap += 1.0;
      del *= x / ap;
      sum += del;
      if (std::fabs(del) < std::fabs(sum) * 1e-15) break;
    }
    return sum * std::exp(-x + a * std::log(x) - gln);
  }
  // Continued fraction for Q(a, x) (modified Lentz).
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::fabs(del - 1.0) < 1e-15) break;
  }
  return 1.0 - std::exp(-x + a * std::log(x) - gln) * h;
}

}  // namespace

double chi_square_cdf(double x, double dof) {
  if (!(dof > 0.0) || !std::isfinite(dof)) {
    throw InputError("chi_square_cdf: dof = " + std::to_string(dof) + ": must be finite and > 0");
  }
  if (!(x >= 0.0)) {
    throw InputError("chi_square_cdf: x = " + std::to_string(x) + ": must be >= 0");
  }
  if (std::isinf(x)) return 1.0;
  return gamma_p(0.5 * dof, 0.5 * x);
}

double chi_square_quantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0)) {
    throw InputError("chi_square_quantile: p = " + std::to_string(p) + ": must be in (0, 1)");
  }
  if (!(dof > 0.0) || !std::isfinite(dof)) {
    throw InputError("chi_square_quantile: dof = " + std::to_string(dof) +
                     ": must be finite and > 0");
  }
  // Bracket, then Newton steps kept inside the bracket (bisection fallback).
  double lo = 0.0, hi = dof + 10.0 * std::sqrt(2.0 * dof) + 10.0;
  while (chi_square_cdf(hi, dof) < p) hi *= 2.0;
  // Wilson-Hilferty start.
  const double k = dof;
  const double zq = [&] {
    // Acklam-free rough normal quantile from a logistic approximation, refined by Newton below.
    const double q = p < 0.5 ? p : 1.0 - p;
    const double t = std::sqrt(-2.0 * std::log(q));
    const double z = t - (2.515517 + 0.802853 * t + 0.010328 * t * t) /
                             (1.0 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t);
    return p < 0.5 ? -z : z;
  }();
  const double c = 2.0 / (9.0 * k);
  double x = k * std::pow(std::max(1.0 - c + zq * std::sqrt(c), 1e-3), 3.0);
  if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double f = chi_square_cdf(x, dof) - p;
    if (f < 0.0) lo = x; else hi = x;
    if (std::fabs(f) < 1e-14 || hi - lo < 1e-13 * std::max(1.0, x)) break;
    const double a = 0.5 * dof;
    const double log_pdf = (a - 1.0) * std::log(x) - 0.5 * x - a * std::log(2.0) - std::lgamma(a);
    const double pdf = std::exp(log_pdf);
    double next = pdf > 0.0 ? x - f / pdf : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    x = next;
  }
  return x;
}

}  // namespace sarloc
