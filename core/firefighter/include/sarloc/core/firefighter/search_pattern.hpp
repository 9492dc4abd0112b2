#pragma once
// Pattern extraction (seed 004 section IV-C, Fig. 3): a square grid over each floor of the map;
// from the node nearest each entry, the node sequence of a right-hand directional search along
// the grid (turn right where the grid lets you, else straight, else left, else back) until it
// returns to the first node (a loop already walked from another start is kept once); then, for
// every group of inner walls that no sequence has gone around (walls not connected to the outer
// walls), a sequence started next to it. Grid edges that cross a wall of the navigation map are
// blocked; nodes closer than `min_clearance_m` to a wall are dropped. Deviation, named: each
// sequence also lists the rooms a search may pass by (RoomSkip), so that a crew that skips a
// room still fits the pattern of the rooms it did search.
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
  /// A search may pass a room by (a real crew skips a room it cannot enter or has searched; the
  /// simulated walker does at `walk.skip_room_probability`): with `room_skips`, every
  /// excursion of `room_skip_min_nodes` or more nodes (a room entered and left by one door) is
  /// also compared without it (RoomSkip, PatternMatcher).
  bool room_skips = true;
  unsigned room_skip_min_nodes = 4;
  void validate() const;
};

/// A room the search may pass by (`walk.skip_room_probability` of the simulated walker; a real
/// crew skips a room it cannot enter or has searched): the walk goes from node `from` straight
/// to node `to`, a grid edge, leaving out the nodes between them (an excursion that leaves the
/// path at `from` and comes back to it).
struct RoomSkip {
  std::size_t from = 0, to = 0;
};

struct NodeSequence {
  std::size_t floor = 0;
  std::vector<Vec2> nodes;
  bool around_inner_walls = false;
  std::vector<RoomSkip> room_skips;  ///< outermost excursions only, `from` < `to`
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
