#pragma once
// The places a particle cloud is in (issue 65: "ambiguous between N places"): its particles in
// 1 m cells per floor, cells that touch (8 neighbours) joined into one place, each place's
// weight and weighted mean and covariance. A cloud over the whole plan is one or a few big
// places; a cloud split between look-alike corridors is a few compact ones.
#include <vector>

#include "sarloc/core/firefighter/map_particle_filter.hpp"

namespace sarloc::firefighter {

/// Every place, heaviest first (weights sum to 1 over all of them).
std::vector<Place> cloud_places(const std::vector<Particle>& particles, const std::vector<double>& weights);

}  // namespace sarloc::firefighter
