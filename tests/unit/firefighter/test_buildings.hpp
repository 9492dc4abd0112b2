#pragma once
// The shipped buildings (config/buildings/) for the firefighter tests.
#include <string>

#include "sarloc/app/floor_plan_yaml.hpp"

namespace sarloc::firefighter::test {

inline FloorPlan building(const std::string& name) {
  return app::load_floor_plan(std::string(SARLOC_SOURCE_DIR) + "/config/buildings/" + name + ".yaml");
}

}  // namespace sarloc::firefighter::test
