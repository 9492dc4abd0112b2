#pragma once
// YAML -> EvaluationSetup for sarloc-eval (config/eval/avalanche.yaml documents every key).
#include <string>

#include "sarloc/core/avalanche/evaluation.hpp"
#include "sarloc/core/firefighter/firefighter_evaluation.hpp"

namespace sarloc::eval {

/// Reads the sections simulation:, sog:, search:, evaluation: over the defaults of `setup`.
/// Unknown keys are errors (ConfigError naming the key path).
void load_avalanche_config(const std::string& path, avalanche::EvaluationSetup& setup);
void load_avalanche_config_text(const std::string& text, const std::string& name,
                                avalanche::EvaluationSetup& setup);

/// Reads the sections walk:, imu:, ins:, pattern:, filter:, evaluation: of
/// config/eval/firefighter.yaml over the defaults of `config` (angles in degrees there).
void load_firefighter_config(const std::string& path, firefighter::FirefighterEvalConfig& config);
void load_firefighter_config_text(const std::string& text, const std::string& name,
                                  firefighter::FirefighterEvalConfig& config);

}  // namespace sarloc::eval
