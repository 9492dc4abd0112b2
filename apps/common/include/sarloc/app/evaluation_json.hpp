#pragma once
// JSON of the evaluations' summaries (sarloc-eval's --json): in a library of their own
// (sarloc_apps_evaluation), so that the product's processes link no evaluation code.
//
//   app::write_json_file(path, app::to_json(summary));
#include <nlohmann/json.hpp>

#include "sarloc/app/json_io.hpp"
#include "sarloc/core/avalanche/evaluation.hpp"
#include "sarloc/core/avalanche/multi_burial.hpp"
#include "sarloc/core/firefighter/firefighter_evaluation.hpp"

namespace sarloc::app {

nlohmann::json to_json(const avalanche::EvaluationSummary& summary);
/// The multiple-burial evaluation: its totals and every trial (found, ghosts, duplicates, ...).
nlohmann::json to_json(const avalanche::MultiBurialSummary& summary);
/// The firefighter evaluation: building, runs, seed, configs[] (name, pseudo_observations,
/// resampling, known_initial_state, rmse_m_at_s, final_rmse_m, converged_fraction,
/// ms_per_update, ...), ins_drift_percent {median, p95}; with the map-error experiment.
nlohmann::json to_json(const firefighter::FirefighterSummary& summary, double rmse_every_s,
                       const firefighter::MapErrorExperiment* map_error = nullptr);

}  // namespace sarloc::app
