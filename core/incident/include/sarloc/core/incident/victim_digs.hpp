#pragma once
// Incident command's dig order (issue 63, item 4): plan_digs (dig_order.hpp) over the picture's
// FOUND victims, each placed by its fused estimate (depth: its height below the snow surface),
// all buried as long as the avalanche is old, dug by the free rescuers.
//
// Diggers: a rescuer is free when its link is alive, it has a GNSS fix, walks no strip and
// pursues no victim. There are as many digging teams as free rescuers (at most one per victim);
// each team's rescuer is the free one nearest to the team's first dig. With nobody free the
// order still stands for one team, its digger empty ("waits for a team"): the order of the
// digs does not wait for diggers.
//
//   const VictimDigs digs = plan_victim_digs(fusion.victims(), free_rescuers, 12.0, TriageConfig{});
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "sarloc/core/incident/deposit.hpp"
#include "sarloc/core/incident/dig_order.hpp"
#include "sarloc/core/incident/fused_victim.hpp"

namespace sarloc::incident {

/// At most this many digs in a plan (the SearchPlan topic's bound); more FOUND victims than
/// that are ranked by the shortest dig and the rest left out of the topic.
inline constexpr std::size_t kVictimDigsMax = 64;

struct VictimDig {
  std::uint32_t victim_id = 0;
  double depth_m = 0.0;     ///< below the snow surface, from the fused estimate
  double buried_min = 0.0;  ///< minutes buried now
  double start_min = 0.0;   ///< from now
  double done_min = 0.0;
  double survival = 0.0;  ///< the survival curve at buried_min + done_min
  std::string digger_id;  ///< "" = no free rescuer yet
};

struct VictimDigs {
  std::vector<VictimDig> digs;  ///< in dig order
  double expected_survivors = 0.0;
};

/// The dig order of `victims` in state FOUND (recovered ones are dug out already), all buried
/// `buried_min` minutes. `free_rescuers`: the free rescuers' positions (incident frame).
/// `first`: an operator's victims to dig first, in that order (plan_digs).
VictimDigs plan_victim_digs(const std::vector<FusedVictim>& victims, const std::map<std::string, Vec2>& free_rescuers,
                            double buried_min, const TriageConfig& triage,
                            const std::vector<std::uint32_t>& first = {});

}  // namespace sarloc::incident
