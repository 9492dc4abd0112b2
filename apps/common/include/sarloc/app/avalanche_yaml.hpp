#pragma once
// YAML sections of the avalanche estimator, shared by sarloc-eval and the mission apps so a
// key means the same everywhere. Each reader consumes one section (a map) over the defaults
// already in the struct and rejects unknown keys; validation is the struct's own validate().
#include <map>
#include <string>

#include "sarloc/app/yaml_reader.hpp"
#include "sarloc/core/avalanche/rescuer_search.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/incident/search_plan.hpp"

namespace sarloc::app {

void read_transmitter_standard(YamlReader section, avalanche::TransmitterStandard& standard);
void read_receiver(YamlReader section, avalanche::ReceiverModelConfig& config);
void read_simulation(YamlReader section, avalanche::SimulationConfig& config);
void read_sog(YamlReader section, avalanche::SogConfig& config);
/// `plan`: a mission file's search: section also holds incident command's primary-search plan
/// (strip_width_m, fall_line_deg, coverage_cell_m, strip_done_fraction, max_walk_step_m,
/// recut_below_searched); null elsewhere (an evaluation plans nothing: the keys are refused).
void read_search(YamlReader section, avalanche::SearchConfig& config, incident::SearchPlanConfig* plan = nullptr);
/// The rescuer_search: section (limits of the input gate, summary size).
void read_rescuer_search(YamlReader section, avalanche::RescuerSearchConfig& config);

/// The receiver's height above the snow is one fact, read under three keys:
/// simulation.antenna_height_m (how the simulated rescuers hold it), sog.antenna_height_m (what
/// the filter assumes) and, in a mission file, command.antenna_height_m (what incident command
/// assumes; `command_height` null elsewhere). The value a file sets under any of them is handed
/// to the others; two keys set to different values are a ConfigError naming both. Call it after
/// the sections were read from `root`.
void hold_one_antenna_height(YamlReader root, avalanche::SimulationConfig& simulation, avalanche::SogConfig& sog,
                             double* command_height);

/// Every parameter of these sections as the readers see it, key path -> value text
/// ("search.opening_line_samples" -> "60"): what a program built from these structs runs.
/// The same keys and texts for equal values, so two programs' parameters compare key by key.
std::map<std::string, std::string> avalanche_parameters(const avalanche::SimulationConfig& simulation,
                                                        const avalanche::SogConfig& sog,
                                                        const avalanche::SearchConfig& search);

}  // namespace sarloc::app
