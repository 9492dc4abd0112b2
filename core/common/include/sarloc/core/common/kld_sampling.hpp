#pragma once
// KLD-sampling (Fox, "Adapting the size of particle filters through KLD-sampling", IJRR 2003):
// how many samples keep, with probability `confidence`, the Kullback-Leibler divergence between
// the sample-based posterior and the true one below `epsilon` when the samples occupy `bins`
// bins of a discretised state space. Few bins (a concentrated posterior) need few samples; a
// posterior spread over the whole map needs many. Eq. (13), with the Wilson-Hilferty
// approximation of the chi-square quantile, as Fox uses it.
//
//   const KldSampleCount needed(0.05, 0.99);
//   while (n < max && (n < min || n < needed(bins_so_far))) draw_one();
#include <cstddef>

namespace sarloc {

class KldSampleCount {
 public:
  /// epsilon > 0: the bound on the KL divergence; confidence in (0.5, 1): 1 - delta.
  KldSampleCount(double epsilon, double confidence);
  /// Samples needed with `bins` occupied bins; 0 for fewer than 2 (one bin holds no spread).
  double operator()(std::size_t bins) const;

 private:
  double epsilon_;
  double z_;  ///< upper 1 - delta quantile of the standard normal
};

}  // namespace sarloc
