#pragma once
// YAML sections of the firefighter estimator, shared by sarloc-eval (filter:) and the mission
// file (firefighter.filter:) so that a mission can set every key the evaluation tunes. The
// reader consumes one section over the defaults already in the struct and rejects unknown keys;
// validation is the struct's own validate().
#include "sarloc/app/yaml_reader.hpp"
#include "sarloc/core/firefighter/map_particle_filter.hpp"

namespace sarloc::app {

void read_map_filter(YamlReader section, firefighter::MapFilterConfig& config);

}  // namespace sarloc::app
