#pragma once
// The places a particle cloud is in (issue 65: "ambiguous between N places"): its particles in
// 1 m cells per floor, cells that touch (8 neighbours) joined into one place, each place's
// weight and weighted mean and covariance. A cloud over the whole plan is one or a few big
// places; a cloud split between look-alike corridors is a few compact ones.
#include <cstdint>
#include <vector>

#include "sarloc/core/firefighter/map_particle_filter.hpp"

namespace sarloc::firefighter {

/// A cell of a grid over the floors: its floor and its column and row packed in one key.
inline std::uint64_t cell_key(std::size_t floor, std::int64_t ix, std::int64_t iy) {
  return (static_cast<std::uint64_t>(floor) << 48) ^ (static_cast<std::uint64_t>(ix & 0xFFFFFF) << 24) ^
         static_cast<std::uint64_t>(iy & 0xFFFFFF);
}

/// Every place, heaviest first (weights sum to 1 over all of them).
std::vector<Place> cloud_places(const std::vector<Particle>& particles, const std::vector<double>& weights);

}  // namespace sarloc::firefighter
