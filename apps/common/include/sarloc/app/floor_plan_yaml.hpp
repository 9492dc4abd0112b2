#pragma once
// YAML -> firefighter::FloorPlan (docs/configuration.md, "Floor plans"). Strict: unknown keys,
// missing keys, wrong types and every FloorPlan::validate() rule are ConfigErrors naming the
// file and the element ("house.yaml: floors[0].walls[3].b ...", "floors[ground].doors[d1]: ...").
// load_floor_plan also reads an IMDF directory (floor_plan_imdf.hpp).
#include <string>

#include "sarloc/core/firefighter/floor_plan.hpp"

namespace sarloc::app {

firefighter::FloorPlan load_floor_plan(const std::string& path);
firefighter::FloorPlan load_floor_plan_text(const std::string& text, const std::string& name);
/// The plan as the YAML this loader reads (exact numbers): how a recording carries a plan that
/// was imported (an IMDF directory is no file to attach).
std::string floor_plan_yaml_text(const firefighter::FloorPlan& plan);

}  // namespace sarloc::app
