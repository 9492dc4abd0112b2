#include "sarloc/core/common/kld_sampling.hpp"

#include <cmath>
#include <string>

#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc {

KldSampleCount::KldSampleCount(double epsilon, double confidence) : epsilon_(epsilon) {
  if (!(epsilon > 0.0 && std::isfinite(epsilon))) {
    throw InputError("KLD-sampling epsilon = " + std::to_string(epsilon) + ": must be > 0");
  }
  if (!(confidence > 0.5 && confidence < 1.0)) {
    throw InputError("KLD-sampling confidence = " + std::to_string(confidence) + ": must be within (0.5, 1)");
  }
  // z with Phi(z) = confidence: z^2 is chi2(1)'s quantile at 1 - 2 (1 - confidence).
  z_ = std::sqrt(chi_square_quantile(2.0 * confidence - 1.0, 1.0));
}

double KldSampleCount::operator()(std::size_t bins) const {
  if (bins < 2) return 0.0;
  const double k1 = static_cast<double>(bins - 1);
  const double a = 2.0 / (9.0 * k1);
  const double cube = 1.0 - a + std::sqrt(a) * z_;
  return k1 / (2.0 * epsilon_) * cube * cube * cube;
}

}  // namespace sarloc
