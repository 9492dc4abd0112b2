#pragma once
// Pattern extraction (seed 004 section IV-C, Fig. 3): a square grid over each floor of the map;
// from the node nearest each entry, the node sequence of a right-hand directional search along
// the grid (turn right where the grid lets you, else straight, else left, else back) until it
// returns to the first node (a loop already walked from another start is kept once); then, for
// every group of inner walls that no sequence has gone around (walls not connected to the outer
// walls), a sequence started next to it. Grid edges that cross a wall of the navigation map are
// blocked; nodes closer than `min_clearance_m` to a wall are dropped.
//
//   auto sequences = extract_node_sequences(plan, PatternGridConfig{});
//   // sequences[m].nodes: p_1 ... p_N (p_N adjacent to p_1)
#include <cstddef>
#include <vector>

#include "sarloc/core/firefighter/floor_plan.hpp"

namespace sarloc::firefighter {

struct PatternGridConfig {
  double spacing_m = 1.0;        ///< seed 004 section V-B
  double min_clearance_m = 0.2;
  void validate() const;
};

struct NodeSequence {
  std::size_t floor = 0;
  std::vector<Vec2> nodes;
  bool around_inner_walls = false;
};

/// Grid nodes reachable from the entries (and, on upper floors, from the top of the stairs):
/// the navigable area of each floor, one node per spacing^2.
struct NavigableGrid {
  double spacing_m = 1.0;
  std::vector<std::vector<Vec2>> nodes_per_floor;
  double area_m2(std::size_t floor) const;
};

NavigableGrid navigable_grid(const FloorPlan& plan, const PatternGridConfig& config);
std::vector<NodeSequence> extract_node_sequences(const FloorPlan& plan, const PatternGridConfig& config);

}  // namespace sarloc::firefighter
