#include "sarloc/app/evaluation_json.hpp"

#include <cmath>

namespace sarloc::app {
namespace {

nlohmann::json stats_json(const avalanche::Stats& s) { return {{"max", s.max}, {"mean", s.mean}, {"median", s.median}}; }

}  // namespace

nlohmann::json to_json(const avalanche::MultiBurialSummary& s) {
  nlohmann::json j;
  j["victims"] = s.victims;
  j["spread_m"] = s.spread_m;
  j["trials"] = s.trials;
  j["seed"] = s.seed;
  j["all_found"] = s.all_found;
  j["ghosts"] = s.ghosts;
  j["duplicates"] = s.duplicates;
  j["founds"] = s.founds;
  j["founds_outside_radius"] = s.founds_outside_radius;
  j["worst_found_error_to_radius"] = s.worst_found_error_to_radius;
  j["located_signals"] = s.located_signals;
  j["false_located"] = s.false_located;
  j["trials_with_false_located"] = s.trials_with_false_located;
  j["worst_false_located_range_m"] = s.worst_false_located_range_m;
  j["first_located_range_m"] = stats_json(s.first_located_range_m);
  j["repeats_retired"] = s.repeats_retired;
  j["repeats_wrong"] = s.repeats_wrong;
  j["repeats_suspected"] = s.repeats_suspected;
  j["trials_with_repeats"] = s.trials_with_repeats;
  j["leaps"] = s.leaps;
  j["trials_with_leaps"] = s.trials_with_leaps;
  j["implausible_rebuilds"] = s.implausible_rebuilds;
  j["trials_with_implausible_rebuilds"] = s.trials_with_implausible_rebuilds;
  j["withdrawn_founds"] = s.withdrawn_founds;
  j["trials_with_withdrawn_founds"] = s.trials_with_withdrawn_founds;
  j["line_resumptions"] = s.line_resumptions;
  j["trials_with_line_resumptions"] = s.trials_with_line_resumptions;
  j["deferred_founds"] = s.deferred_founds;
  j["trials_with_deferred_founds"] = s.trials_with_deferred_founds;
  j["wrong_attributions"] = s.wrong_attributions;
  j["unattributed_pulses"] = s.unattributed_pulses;
  j["mixed_samples"] = s.mixed_samples;
  j["mixed_samples_both_tracked"] = s.mixed_samples_both_tracked;
  j["trials_with_mixed_samples"] = s.trials_with_mixed_samples;
  j["steps"] = stats_json(s.steps);
  j["distance_m"] = stats_json(s.distance_m);
  j["wall_s"] = s.wall_s;
  j["per_trial"] = nlohmann::json::array();
  for (const auto& t : s.per_trial) {
    nlohmann::json records = nlohmann::json::array();
    for (const auto& r : t.found_records)
      records.push_back({{"step", r.step}, {"depth_m", r.depth_m}, {"range_m", r.range_m}, {"error_m", r.error_m},
                         {"radius95_m", r.radius95_m}, {"nees", r.nees}, {"ghost", r.ghost}});
    j["per_trial"].push_back({{"index", t.index},
                              {"found_records", records},
                              {"found", t.found},
                              {"all_found", t.all_found},
                              {"ghosts", t.ghosts},
                              {"duplicates", t.duplicates},
                              {"founds", t.founds},
                              {"founds_outside_radius", t.founds_outside_radius},
                              {"worst_found_error_to_radius", t.worst_found_error_to_radius},
                              {"located_signals", t.located_signals},
                              {"false_located", t.false_located},
                              {"worst_false_located_range_m", t.worst_false_located_range_m},
                              {"first_located_range_m", t.first_located_range_m},
                              {"repeats_retired", t.repeats_retired},
                              {"repeats_wrong", t.repeats_wrong},
                              {"repeats_suspected", t.repeats_suspected},
                              {"leaps", t.leaps},
                              {"implausible_rebuilds", t.implausible_rebuilds},
                              {"withdrawn_founds", t.withdrawn_founds},
                              {"line_resumptions", t.line_resumptions},
                              {"deferred_founds", t.deferred_founds},
                              {"wrong_attributions", t.wrong_attributions},
                              {"unattributed_pulses", t.unattributed_pulses},
                              {"mixed_samples", t.mixed_samples},
                              {"mixed_samples_both_tracked", t.mixed_samples_both_tracked},
                              {"steps", t.steps},
                              {"distance_m", t.distance_m},
                              {"signals", t.signals},
                              {"min_carrier_gap_hz", t.min_carrier_gap_hz},
                              {"lockstep_s", std::isfinite(t.lockstep_s) ? t.lockstep_s : -1.0}});
  }
  return j;
}

nlohmann::json to_json(const avalanche::EvaluationSummary& s) {
  nlohmann::json j;
  j["filter"] = s.filter;
  j["trials"] = s.trials;
  j["seed"] = s.seed;
  j["error_m"] = stats_json(s.error_m);
  j["initial_distance_m"] = stats_json(s.initial_distance_m);
  j["steps"] = stats_json(s.steps);
  j["not_found"] = s.not_found;
  j["errors_over_1m"] = s.errors_over_1m;
  j["receiver"] = s.receiver;
  j["false_found"] = s.false_found;
  j["found_by_probe_pattern"] = s.found_by_probe_pattern;
  j["resumed_line"] = s.resumed_line;
  j["ms_per_step"] = {{"median", s.ms_per_step_median}, {"p95", s.ms_per_step_p95}};
  j["nees"] = {{"mean", s.nees_mean},
               {"fraction_inside_95", s.nees_fraction_inside_95},
               {"lower_95", s.nees_lower},
               {"upper_95", s.nees_upper},
               {"trials", s.nees_trials}};
  j["wall_s"] = s.wall_s;
  nlohmann::json trials = nlohmann::json::array();
  for (const auto& t : s.per_trial) {
    double nees_mean = 0.0;
    for (double v : t.nees) nees_mean += v;
    if (!t.nees.empty()) nees_mean /= static_cast<double>(t.nees.size());
    trials.push_back({{"index", t.index},
                      {"found", t.found},
                      {"error_m", t.error_m},
                      {"horizontal_error_m", t.horizontal_error_m},
                      {"initial_distance_m", t.initial_distance_m},
                      {"steps", t.steps},
                      {"flux_line_steps", t.flux_line_steps},
                      {"first_converged_step", t.first_converged_step},
                      {"reinitialisations", t.reinitialisations},
                      {"nees_mean", nees_mean},
                      {"nees_samples", t.nees.size()},
                      {"final_nees", t.final_nees},
                      {"final_components", t.final_components},
                      {"radius95_m", t.radius95_m},
                      {"false_found", t.false_found},
                      {"probe_points", t.probe_points},
                      {"found_by_probe_pattern", t.found_by_probe_pattern},
                      {"line_resumptions", t.line_resumptions}});
  }
  j["per_trial"] = trials;
  return j;
}

nlohmann::json to_json(const firefighter::FirefighterSummary& s, double rmse_every_s,
                       const firefighter::MapErrorExperiment* map_error) {
  nlohmann::json configs = nlohmann::json::array();
  for (const auto& v : s.variants) {
    nlohmann::json at = nlohmann::json::object();
    for (std::size_t j = 0; j < v.rmse_at_s.size(); ++j) {
      at[std::to_string(static_cast<long>(std::lround(rmse_every_s * static_cast<double>(j + 1))))] = v.rmse_at_s[j];
    }
    configs.push_back({{"name", v.variant.name},
                       {"pseudo_observations", v.variant.pseudo_observations},
                       {"resampling", firefighter::to_string(v.variant.resampling)},
                       {"known_initial_state", v.variant.known_initial_state},
                       {"rmse_m_at_s", at},
                       {"final_rmse_m", v.final_rmse_m},
                       {"overall_rmse_m", v.overall_rmse_m},
                       {"converged_fraction", v.converged_fraction},
                       {"wrong_floor_fraction", v.wrong_floor_fraction},
                       {"ms_per_update", v.ms_per_update_amortised},
                       {"ms_per_comparison", v.ms_per_comparison_median},
                       {"ms_per_filter_step", v.ms_per_update_median},
                       {"ms_per_filter_step_mean", v.ms_per_update_mean},
                       {"particles_mean", v.particles_mean},
                       {"converged_wrong_fraction", v.converged_wrong_fraction},
                       {"confirmed_share", v.confirmed_share},
                       {"confirmed_wrong_fraction", v.confirmed_wrong_fraction},
                       {"ambiguous_share", v.ambiguous_share},
                       {"ambiguous_wrong_fraction", v.ambiguous_wrong_fraction},
                       {"false_map_errors_per_hour", v.false_map_errors_per_hour},
                       {"false_map_error_share", v.false_map_error_share},
                       {"nees",
                        {{"mean", v.nees_mean},
                         {"lower", v.nees_lower},
                         {"upper", v.nees_upper},
                         {"members", v.nees_members},
                         {"fraction_inside_95", v.nees_fraction_inside_95}}}});
  }
  nlohmann::json j = {{"building", s.building},
                      {"runs", s.runs},
                      {"seed", s.seed},
                      {"members", s.members},
                      {"duration_s", s.duration_s},
                      {"area_m2", s.area_m2},
                      {"pattern_windows", s.pattern_windows},
                      {"ms_per_comparison_median", s.ms_per_comparison_median},
                      {"distance_median_m", s.distance_median_m},
                      {"members_on_floor", s.members_on_floor},
                      {"ins_drift_percent",
                       {{"median", s.ins_drift_median}, {"p95", s.ins_drift_p95}, {"per_member", s.ins_drift_percent}}},
                      {"configs", configs},
                      {"wall_s", s.wall_s}};
  if (map_error) {
    nlohmann::json timeline = nlohmann::json::array();
    for (const auto& m : map_error->timeline) {
      timeline.push_back({{"t_s", m.t}, {"variance_m2", m.variance_m2}, {"error_m", m.error_m},
                          {"converged", m.converged}, {"map_error_suspected", m.map_error_suspected}});
    }
    j["map_error"] = {{"door", map_error->door}, {"shift_m", map_error->shift_m}, {"raised", map_error->raised},
                      {"recovered", map_error->recovered},
                      {"cleared_while_off_s", map_error->cleared_while_off_s}, {"timeline", timeline}};
  }
  return j;
}

}  // namespace sarloc::app
