#include "sarloc/core/common/particle_weights.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sarloc {

std::vector<double> normalised_weights(const std::vector<double>& log_weights) {
  double max_log = -std::numeric_limits<double>::infinity();
  for (double l : log_weights)
    if (std::isfinite(l)) max_log = std::max(max_log, l);
  if (!std::isfinite(max_log)) throw std::invalid_argument("normalised_weights: no finite weight");
  std::vector<double> w(log_weights.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    w[i] = std::isfinite(log_weights[i]) ? std::exp(log_weights[i] - max_log) : 0.0;
    sum += w[i];
  }
  for (double& v : w) v /= sum;
  return w;
}

double effective_sample_size(const std::vector<double>& weights) {
  double s2 = 0.0;
  for (double w : weights) s2 += w * w;
  return s2 > 0.0 ? 1.0 / s2 : 0.0;
}

std::vector<std::size_t> systematic_resample(const std::vector<double>& weights, std::size_t n,
                                             std::mt19937_64& rng) {
  std::vector<std::size_t> out;
  if (weights.empty() || n == 0) return out;
  double total = 0.0;
  for (double w : weights) total += w;
  if (!(total > 0.0)) throw std::invalid_argument("systematic_resample: weights sum to 0");
  out.reserve(n);
  const double step = total / static_cast<double>(n);
  double u = std::uniform_real_distribution<double>(0.0, step)(rng);
  double cumulative = weights[0];
  std::size_t k = 0;
  for (std::size_t j = 0; j < n; ++j, u += step) {
    while (cumulative < u && k + 1 < weights.size()) cumulative += weights[++k];
    out.push_back(k);
  }
  return out;
}

std::size_t draw_index(const std::vector<double>& cumulative, std::mt19937_64& rng) {
  const double u = std::uniform_real_distribution<double>(0.0, cumulative.back())(rng);
  const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), u);
  return std::min(static_cast<std::size_t>(it - cumulative.begin()), cumulative.size() - 1);
}

}  // namespace sarloc
