#pragma once
// Expected survivors of a simulated avalanche mission (issue 63's goal): each victim's survival
// read off the triage curve (incident/dig_order.hpp) at the moment it would be dug out, had its
// finder started digging at the picture's FOUND: minutes buried before the search began, plus
// the mission's minutes to FOUND, plus its dig time, which grows with its true depth.
//
// A victim never FOUND in the picture has no survival; the summary adds, apart, the most it
// could still get: the curve at the mission's end plus its dig time (it cannot be dug out
// sooner). Comparing two missions' expected survivors (the plan against none) is what this is
// for; the curve and the dig time are assumptions (docs/operations/search-planning.md).
//
//   add_survival_outlook(summary, TriageConfig{});
#include "sarloc/core/incident/dig_order.hpp"
#include "sarloc/core/mission/mission_summary.hpp"

namespace sarloc::mission {

/// Fills each victim's dug_out_min and survival, and the summary's expected_survivors and
/// unfound_survival_at_most. ConfigError naming the key for an invalid `triage`.
void add_survival_outlook(MissionSummary& summary, const incident::TriageConfig& triage);

}  // namespace sarloc::mission
