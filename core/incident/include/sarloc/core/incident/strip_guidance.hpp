#pragma once
// The device's half of the search plan (issue 63, item 2): where a rescuer with no signal to
// follow walks, from incident command's SearchPlan and the device's own fix. The plan reaches
// the devices on its own topic, not inside the core daemon's Guidance: a device keeps to its
// strip while the daemon is away, and the daemon stays a per-rescuer filter.
//
// Rules, each with its unit test (tests/unit/incident/strip_guidance_test.cpp):
//   - only the rescuer's own strip, while it is not done and has a next point; a helper
//     (search_plan.hpp) the strip it helps on, walked the other way: from the bottom up;
//   - walk straight to the next point (the first row of the strip not yet searched: usually a
//     hearing range ahead, so the target moves ahead of a rescuer on the centreline);
//   - within `arrive_m` of it (the plan lags its walk by a cycle), walk on down the strip (a
//     helper: up);
//   - past the strip's far end: nothing (the plan frees the rescuer; its next strip comes);
//   - a fix without a finite position or heading gives nothing.
//
//   if (!guidance) guidance = incident::strip_guidance(plan, "r1", fix, StripGuidanceConfig{});
#include <optional>
#include <string>

#include "sarloc/core/incident/search_plan.hpp"
#include "sarloc/core/responder/guidance.hpp"
#include "sarloc/core/responder/responder_position.hpp"

namespace sarloc::incident {

struct StripGuidanceConfig {
  double step_m = 1.0;    ///< the nominal step (search.step_length_m)
  double arrive_m = 3.0;  ///< closer than this to the next point, walk on down the strip
};

/// Guidance (mode kPrimarySearch, signal 0) along the rescuer's strip, or nullopt (see above).
std::optional<responder::Guidance> strip_guidance(const SearchPlanPicture& picture, const std::string& rescuer_id,
                                                  const responder::ResponderPosition& fix,
                                                  const StripGuidanceConfig& config);

}  // namespace sarloc::incident
