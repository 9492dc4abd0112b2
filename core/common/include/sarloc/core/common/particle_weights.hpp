#pragma once
// Particle weights and resampling, written once for every particle filter of sarloc (the
// avalanche baselines of seed 000 section IV and the firefighter's map-aided filter of seed 004).
//
//   std::vector<double> w = normalised_weights(log_w);     // max-shifted, sums to 1
//   if (effective_sample_size(w) < 0.5 * w.size())        // seed 000, eq. (20)
//     for (std::size_t j : systematic_resample(w, w.size(), rng)) ...
#include <cstddef>
#include <random>
#include <vector>

namespace sarloc {

/// exp(log_w - max) / sum: linear weights summing to 1. Throws std::invalid_argument when no
/// weight is finite (the caller decides what a collapse means).
std::vector<double> normalised_weights(const std::vector<double>& log_weights);

/// N_eff = 1 / sum w_i^2 for weights summing to 1 (seed 000, eq. (20)).
double effective_sample_size(const std::vector<double>& weights);

/// n indices drawn in proportion to `weights` (need not sum to 1) with one uniform offset:
/// systematic resampling, the lowest-variance of the standard schemes (Douc et al. 2005), in
/// ascending order.
std::vector<std::size_t> systematic_resample(const std::vector<double>& weights, std::size_t n,
                                             std::mt19937_64& rng);

/// One index drawn with probability proportional to the increments of `cumulative` (a running
/// sum of non-negative weights, last element > 0).
std::size_t draw_index(const std::vector<double>& cumulative, std::mt19937_64& rng);

}  // namespace sarloc
