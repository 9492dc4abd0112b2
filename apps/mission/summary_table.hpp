#pragma once
// sarloc-mission's printed summary: per victim (truth, fused estimate, error, finder, time to
// locate, found, by whom), per rescuer and firefighter device, the picture's alarms and links,
// handovers, and one closing line.
#include <string>

#include "sarloc/core/mission/mission_summary.hpp"

namespace sarloc::app {

void print_summary(const mission::MissionSummary& summary, const std::string& run_dir);

}  // namespace sarloc::app
