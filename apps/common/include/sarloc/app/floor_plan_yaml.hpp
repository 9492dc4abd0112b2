#pragma once
// YAML -> firefighter::FloorPlan (docs/configuration.md, "Floor plans"). Strict: unknown keys,
// missing keys, wrong types and every FloorPlan::validate() rule are ConfigErrors naming the
// file and the element ("house.yaml: floors[0].walls[3].b ...", "floors[ground].doors[d1]: ...").
#include <string>

#include "sarloc/core/firefighter/floor_plan.hpp"

namespace sarloc::app {

firefighter::FloorPlan load_floor_plan(const std::string& path);
firefighter::FloorPlan load_floor_plan_text(const std::string& text, const std::string& name);

}  // namespace sarloc::app
