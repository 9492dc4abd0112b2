#include "sarloc/core/mission/survival_outlook.hpp"

#include <algorithm>
#include <cmath>

#include "sarloc/core/common/validate.hpp"

namespace sarloc::mission {

void add_survival_outlook(MissionSummary& s, const incident::TriageConfig& triage) {
  triage.validate();
  const double buried_before_start_min = triage.buried_before_start_min;
  double survivors = 0.0;
  s.unfound_survival_at_most = 0.0;
  s.unfound_count = 0;
  for (auto& v : s.victims) {
    const double depth_m = std::max(0.0, -v.true_position.z());  // snow surface z = 0
    const double dig_min = triage.dig_minutes(depth_m);
    if (v.found && v.found_at_s) {
      v.dug_out_min = buried_before_start_min + *v.found_at_s / 60.0 + dig_min;
      v.survival = triage.survival(*v.dug_out_min);
      survivors += *v.survival;
    } else {
      v.dug_out_min.reset();
      v.survival.reset();
      s.unfound_survival_at_most += triage.survival(buried_before_start_min + s.mission_s / 60.0 + dig_min);
      ++s.unfound_count;
    }
  }
  s.expected_survivors = survivors;
}

}  // namespace sarloc::mission
