#pragma once
// Ground truth for simulated searches: a team of two doing a left- or right-hand directional
// search (seed 004 section II, Fig. 1) through a building, as footfalls of each member's
// IMU boot. The leader is a continuous wall follower steered by range to the walls of the
// simulated world (furniture included) at a varying offset; it sweeps, stops, turns back,
// crawls stretches and sometimes skips a room. The second member steps where the leader stepped,
// a little later.
//
// Deliberately independent of the pattern extraction (search_pattern.hpp): no grid, no node
// sequences, so that the filter is never handed the very pattern it looks for.
//
//   std::mt19937_64 rng(seed);
//   SearchWalk walk = generate_search_walk(plan, SearchWalkConfig{}, Hand::kRight, rng);
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "sarloc/core/firefighter/floor_plan.hpp"
#include "sarloc/core/firefighter/foot_trajectory.hpp"

namespace sarloc::firefighter {

enum class Hand { kRight, kLeft };
const char* to_string(Hand hand);

struct SearchWalkConfig {
  double duration_s = 300.0;  ///< searching, after standing at the entry
  double standing_s = 10.0;   ///< at the entry before going in (the INS aligns meanwhile)
  // Walking speeds of a primary search (seed 004 section II: slow, with stops, sweeps and
  // crawling); drawn per search.
  double speed_min_mps = 0.3;
  double speed_max_mps = 0.6;
  double crawl_speed_mps = 0.15;
  double stride_m = 0.8;        ///< of the IMU boot (two steps)
  double crawl_stride_m = 0.35;
  double stance_fraction = 0.55;
  double offset_min_m = 0.3;    ///< from the followed wall, re-drawn every few metres
  double offset_max_m = 0.8;
  double stop_per_m = 0.02;     ///< stops (3-10 s)
  double sweep_per_m = 0.12;    ///< the other foot sweeps (1-3 s on this boot)
  double turn_back_per_m = 0.01;///< walk back 1-3 m and turn again
  double crawl_per_m = 0.01;    ///< crawl 2-5 m
  double skip_room_probability = 0.15;
  double follower_delay_s = 1.5;
  void validate() const;
};

struct SearchWalk {
  Hand hand = Hand::kRight;
  std::string entry;
  std::vector<Footfall> leader;
  std::vector<Footfall> follower;
  double distance_m = 0.0;  ///< walked by the leader
};

/// Throws ConfigError for an invalid config or a plan without entries.
SearchWalk generate_search_walk(const FloorPlan& plan, const SearchWalkConfig& config, Hand hand,
                                std::mt19937_64& rng);

/// The same from the entry `entry_id` (ConfigError naming it when the plan has none such).
SearchWalk generate_search_walk(const FloorPlan& plan, const SearchWalkConfig& config, Hand hand,
                                const std::string& entry_id, std::mt19937_64& rng);

/// How a crew stands at `entry` before a `hand` search: turned from walking in to the wall it
/// will follow ("turn right at each entry point", left for a left-hand search). The heading
/// (rad, map frame) the simulated walk starts with, and the one the live filter assumes for the
/// boot INS that aligned there.
double stance_heading(const Entry& entry, Hand hand);

/// Where a crew aligns its boot INS before a `hand` search from the plan's entry `entry_id`:
/// the entry's position (map frame), its floor's index, and stance_heading (not wrapped). The
/// simulated device's first fix and the live filter's known start are both this pose.
struct EntryStance {
  Vec2 position = Vec2::Zero();
  std::size_t floor = 0;
  double heading_rad = 0.0;
};
/// Nothing when the plan has no entry of that id.
std::optional<EntryStance> entry_stance(const FloorPlan& plan, const std::string& entry_id, Hand hand);

/// Horizontal length of the footfall path.
double path_length(const std::vector<Footfall>& footfalls);

}  // namespace sarloc::firefighter
