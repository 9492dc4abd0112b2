#pragma once
// Which victim of the incident picture is which buried victim: for evaluating a simulated
// mission (sarloc-mission) and for post-mission reports where the truth is known.
#include <vector>

#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/mission/mission_scenario.hpp"

namespace sarloc::mission {

/// Fused victims at most this far (m) from a buried one can be matched to it.
inline constexpr double kMatchRadiusM = 5.0;

/// One-to-one minimum-total-distance assignment of fused victims to buried ones: a fused victim
/// is matched only to the buried victim nearest to it, and never further than radius_m;
/// confirmed ones first (as many as can be matched), unconfirmed ones to what is left. The
/// index of the fused victim per buried victim, -1 when none.
std::vector<int> match_to_truth(const std::vector<VictimSpec>& truth, const std::vector<incident::FusedVictim>& fused,
                                double radius_m = kMatchRadiusM);

/// Every buried victim is matched by a FOUND (or recovered) victim of the picture. Not "as
/// many FOUND as buried": a duplicate whose disposal is still on its way must not count.
bool every_victim_found(const std::vector<VictimSpec>& truth, const std::vector<incident::FusedVictim>& fused);

}  // namespace sarloc::mission
