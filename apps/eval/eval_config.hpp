#pragma once
// YAML -> EvaluationSetup for sarloc-eval (config/eval/avalanche.yaml documents every key).
#include <string>

#include "sarloc/app/yaml_reader.hpp"
#include "sarloc/core/avalanche/evaluation.hpp"
#include "sarloc/core/avalanche/multi_burial.hpp"
#include "sarloc/core/firefighter/firefighter_evaluation.hpp"

namespace sarloc::eval {

/// Reads the sections simulation:, sog:, search:, evaluation: over the defaults of `setup`.
/// Unknown keys are errors (ConfigError naming the key path).
void load_avalanche_config(const std::string& path, avalanche::EvaluationSetup& setup);
void load_avalanche_config_text(const std::string& text, const std::string& name,
                                avalanche::EvaluationSetup& setup);

/// What `sarloc-eval multi-burial -c FILE` runs: `base`'s estimator sections (the rescuer's SOG
/// filter and search, the simulation), its seed and threads, `trials` trials and a step budget
/// of 200 per victim at least. Not validated (the caller may change it first).
avalanche::MultiBurialSetup multi_burial_setup(const avalanche::EvaluationSetup& base, std::uint32_t victims,
                                               double spread_m, std::uint32_t trials);

/// The ins: section (config/eval/firefighter.yaml, `sarloc-eval ins -c`) over `config`.
void read_ins(app::YamlReader section, firefighter::ZuptInsConfig& config);

/// Reads the sections walk:, imu:, ins:, pattern:, filter:, evaluation: of
/// config/eval/firefighter.yaml over the defaults of `config` (angles in degrees there).
void load_firefighter_config(const std::string& path, firefighter::FirefighterEvalConfig& config);
void load_firefighter_config_text(const std::string& text, const std::string& name,
                                  firefighter::FirefighterEvalConfig& config);

}  // namespace sarloc::eval
