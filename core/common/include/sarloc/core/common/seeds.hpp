#pragma once
// Per-trial random seeds from one evaluation seed, so that Monte Carlo figures depend on the
// seed and the trial index only (never on the thread count or the order trials finish).
#include <cstdint>

namespace sarloc {

/// Seed of trial `index` from the evaluation seed (splitmix64).
std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t index);

}  // namespace sarloc
