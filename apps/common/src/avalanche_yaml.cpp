#include "sarloc/app/avalanche_yaml.hpp"

#include <cmath>
#include <utility>
#include <vector>

#include "sarloc/core/common/validate.hpp"

namespace sarloc::app {

void read_transmitter_standard(YamlReader r, avalanche::TransmitterStandard& s) {
  r.read("field_min_A_per_m", s.field_min_A_per_m);
  r.read("field_max_A_per_m", s.field_max_A_per_m);
  r.read("reference_distance_m", s.reference_distance_m);
  r.expect_done();
}

void read_receiver(YamlReader r, avalanche::ReceiverModelConfig& c) {
  std::string kind = avalanche::to_string(c.kind);
  r.read("kind", kind);
  c.kind = avalanche::parse_receiver_kind(kind, "simulation.receiver.kind");
  r.read("carrier_hz", c.carrier_hz);
  r.read("short_axis_noise_factor", c.short_axis_noise_factor);
  r.read("detect_snr", c.detect_snr);
  r.read("gain_sigma", c.gain_sigma);
  r.read("calibration_relative", c.calibration_relative);
  r.read("misalignment_sigma_deg", c.misalignment_sigma_deg);
  r.read("phase_coherent", c.phase_coherent);
  r.read("period_min_ms", c.period_min_ms);
  r.read("period_max_ms", c.period_max_ms);
  r.read("on_time_min_ms", c.on_time_min_ms);
  r.read("on_time_max_ms", c.on_time_max_ms);
  r.read("carrier_tolerance_hz", c.carrier_tolerance_hz);
  r.read("oscillator_sigma_ppm", c.oscillator_sigma_ppm);
  r.read("sample_rate_hz", c.sample_rate_hz);
  r.read("two_tone_span_hz", c.two_tone_span_hz);
  r.read("same_carrier_pairs", c.same_carrier_pairs);
  r.read("continuous_listening", c.continuous_listening);
  r.expect_done();
}

void read_simulation(YamlReader r, avalanche::SimulationConfig& c) {
  r.read("start_distance_min_m", c.start_distance_min_m);
  r.read("start_distance_max_m", c.start_distance_max_m);
  r.read("burial_depth_p95_m", c.burial_depth_p95_m);
  r.read("min_burial_depth_m", c.min_burial_depth_m);
  r.read("antenna_height_m", c.antenna_height_m);
  read_transmitter_standard(r.child("standard"), c.standard);
  r.read("field_noise_relative", c.field_noise_relative);
  r.read("field_noise_floor_A_per_m", c.field_noise_floor_A_per_m);
  r.read("odometry_translation_relative", c.odometry_translation_relative);
  r.read("odometry_translation_floor_m", c.odometry_translation_floor_m);
  r.read("odometry_yaw_sigma_deg", c.odometry_yaw_sigma_deg);
  r.read("odometry_roll_pitch_sigma_deg", c.odometry_roll_pitch_sigma_deg);
  r.read("sway_roll_pitch_deg", c.sway_roll_pitch_deg);
  r.read("attitude_roll_pitch_sigma_deg", c.attitude_roll_pitch_sigma_deg);
  r.read("attitude_yaw_sigma_deg", c.attitude_yaw_sigma_deg);
  r.read("attitude_updates", c.attitude_updates);
  r.read("primary_strip_half_width_m", c.primary_strip_half_width_m);
  read_receiver(r.child("receiver"), c.receiver);
  r.expect_done();
}

void read_sog(YamlReader r, avalanche::SogConfig& c) {
  r.read("initial_components", c.initial_components);
  read_transmitter_standard(r.child("standard"), c.standard);
  r.read("antenna_height_m", c.antenna_height_m);
  r.read("max_burial_depth_m", c.max_burial_depth_m);
  r.read("depth_layers", c.depth_layers);
  r.read("depth_sigma_factor", c.depth_sigma_factor);
  r.read("near_field_depth_sigma_per_range", c.near_field_depth_sigma_per_range);
  r.read("near_field_burial_depth_m", c.near_field_burial_depth_m);
  r.read("near_field_initial_components", c.near_field_initial_components);
  r.read("horizontal_overlap", c.horizontal_overlap);
  r.read("max_range_m", c.max_range_m);
  r.read("range_noise_sigmas", c.range_noise_sigmas);
  r.read("moment_margin", c.moment_margin);
  r.read("jacobian_initial_weights", c.jacobian_initial_weights);
  r.read("attitude_prior_sigma_rad", c.attitude_prior_sigma_rad);
  r.read("noise_relative", c.noise_relative);
  r.read("noise_floor_A_per_m", c.noise_floor_A_per_m);
  r.read("field_carrier_hz", c.field_carrier_hz);
  r.read("calibration_gain_sigma", c.calibration_gain_sigma);
  r.read("calibration_pointing_sigma_deg", c.calibration_pointing_sigma_deg);
  r.read("censored_axis_sigmas", c.censored_axis_sigmas);
  r.read("censored_axes_in_update", c.censored_axes_in_update);
  r.read("idle_translation_sigma_m", c.idle_translation_sigma_m);
  r.read("idle_rotation_sigma_rad", c.idle_rotation_sigma_rad);
  r.read("use_orientation", c.use_orientation);
  r.read("surface_constraint", c.surface_constraint);
  r.read("moment_constraint", c.moment_constraint);
  r.read("reinit_gate_probability", c.reinit_gate_probability);
  r.read("reinit_after", c.reinit_after);
  r.read("divergence_window", c.divergence_window);
  r.read("converged_divergence_ratio", c.converged_divergence_ratio);
  r.read("leap_gate_probability", c.leap_gate_probability);
  r.read("leap_min_range_m", c.leap_min_range_m);
  r.read("window_fit_samples", c.window_fit_samples);
  r.read("window_region_probability", c.window_region_probability);
  r.read("implausible_rebuild_steps", c.implausible_rebuild_steps);
  r.read("iterated_update_max", c.iterated_update_max);
  r.read("relinearise_threshold_sigmas", c.relinearise_threshold_sigmas);
  r.read("negative_information", c.negative_information);
  r.read("miss_detection_statistic", c.miss_detection_statistic);
  r.read("miss_power_margin", c.miss_power_margin);
  r.read("miss_weight_floor", c.miss_weight_floor);
  r.read("prune_log_weight", c.prune_log_weight);
  r.read("merge_interval", c.merge_interval);
  r.read("merge_cell_m", c.merge_cell_m);
  r.read("merge_mahalanobis", c.merge_mahalanobis);
  r.read("max_components", c.max_components);
  r.read("converged_radius_m", c.converged_radius_m);
  r.expect_done();
}

void read_search(YamlReader r, avalanche::SearchConfig& c, incident::SearchPlanConfig* plan) {
  if (plan != nullptr) {  // a mission's: incident command's primary-search plan (search_plan.hpp)
    r.read("strip_width_m", plan->strips.strip_width_m);
    if (r.has("fall_line_deg")) {
      double deg = 0.0;
      r.read("fall_line_deg", deg);
      plan->strips.fall_line_deg = deg;
    }
    r.read("coverage_cell_m", plan->coverage_cell_m);
    r.read("strip_done_fraction", plan->strip_done_fraction);
    r.read("max_walk_step_m", plan->max_walk_step_m);
    r.read("recut_below_searched", plan->recut_below_searched);
    r.read("pursuit_timeout_s", plan->pursuit_timeout_s);
  }
  r.read("step_length_m", c.step_length_m);
  r.read("approach_mahalanobis", c.approach_mahalanobis);
  r.read("approach_radius_fraction", c.approach_radius_fraction);
  r.read("fine_search_radius_m", c.fine_search_radius_m);
  r.read("located_radius_m", c.located_radius_m);
  r.read("located_radius_per_range", c.located_radius_per_range);
  r.read("located_radius_max_m", c.located_radius_max_m);
  r.read("found_distance_m", c.found_distance_m);
  r.read("confirm_min_samples", c.confirm_min_samples);
  r.read("confirm_max_innovation_ratio", c.confirm_max_innovation_ratio);
  r.read("confirm_innovation_window", c.confirm_innovation_window);
  r.read("confirm_max_last_nis", c.confirm_max_last_nis);
  r.read("confirm_probe_window", c.confirm_probe_window);
  r.read("confirm_probe_gate_probability", c.confirm_probe_gate_probability);
  r.read("confirm_window_reach_factor", c.confirm_window_reach_factor);
  r.read("found_confirmations", c.found_confirmations);
  r.read("confirm_max_waits", c.confirm_max_waits);
  r.read("confirm_probe_per_depth", c.confirm_probe_per_depth);
  r.read("probe_step_m", c.probe_step_m);
  r.read("flux_smoothing", c.flux_smoothing);
  r.read("flux_snr_cap", c.flux_snr_cap);
  r.read("flux_detection_snr2", c.flux_detection_snr2);
  std::string opening = avalanche::to_string(c.opening_heading);
  r.read("opening_heading", opening);
  c.opening_heading = avalanche::parse_opening_heading(opening);
  r.read("opening_line_samples", c.opening_line_samples);
  r.read("coast_return_m", c.coast_return_m);
  r.read("lost_signal_steps", c.lost_signal_steps);
  r.read("lost_line_half_length_m", c.lost_line_half_length_m);
  r.read("bearing_kernel_deg", c.bearing_kernel_deg);
  r.read("bearing_switch_ratio", c.bearing_switch_ratio);
  r.read("lookahead_hypotheses", c.lookahead.hypotheses);
  r.read("lookahead_headings", c.lookahead.headings);
  r.read("lookahead_horizon_steps", c.lookahead.horizon_steps);
  r.read("lookahead_detour_weight", c.lookahead.detour_weight);
  r.read("lookahead_information_scale", c.lookahead.information_scale);
  r.read("stall_window_steps", c.stall_window_steps);
  r.read("stall_min_improvement", c.stall_min_improvement);
  r.expect_done();
}

void read_rescuer_search(YamlReader r, avalanche::RescuerSearchConfig& c) {
  unsigned summary = static_cast<unsigned>(c.summary_components);
  r.read("summary_components", summary);
  c.summary_components = summary;
  r.read("max_signals", c.max_signals);
  r.read("max_step_m", c.max_step_m);
  r.read("max_rotation_rad", c.max_rotation_rad);
  r.read("unknown_motion_speed_m_per_s", c.unknown_motion_speed_m_per_s);
  r.read("unknown_motion_turn_rad_per_s", c.unknown_motion_turn_rad_per_s);
  r.read("target_silence_s", c.target_silence_s);
  r.read("same_transmitter_gate_probability", c.same_transmitter_gate_probability);
  r.read("same_transmitter_moment_spread", c.same_transmitter_moment_spread);
  r.read("measurement_lag_tolerance_s", c.measurement_lag_tolerance_s);
  r.read("found_witness_window_s", c.found_witness_window_s);
  r.read("found_witness_gate_probability", c.found_witness_gate_probability);
  r.read("found_witness_radius_factor", c.found_witness_radius_factor);
  r.expect_done();
}

std::map<std::string, std::string> avalanche_parameters(const avalanche::SimulationConfig& simulation,
                                                        const avalanche::SogConfig& sog,
                                                        const avalanche::SearchConfig& search) {
  // Reading an empty document changes nothing and records every key's current value.
  YamlReader::ValueRecorder recorder;
  auto empty = YamlReader::from_string("", "parameters");
  auto sim = simulation;
  auto filter = sog;
  auto control = search;
  read_simulation(empty.child("simulation"), sim);
  read_sog(empty.child("sog"), filter);
  read_search(empty.child("search"), control);
  std::map<std::string, std::string> out;
  for (const auto& [key, value] : recorder.values()) out[key] = value.text;
  return out;
}

void hold_one_antenna_height(YamlReader root, avalanche::SimulationConfig& simulation, avalanche::SogConfig& sog,
                             double* command_height) {
  std::vector<std::pair<std::string, double*>> keys{{"simulation", &simulation.antenna_height_m},
                                                    {"sog", &sog.antenna_height_m}};
  if (command_height != nullptr) keys.emplace_back("command", command_height);
  const std::pair<std::string, double*>* first_set = nullptr;
  for (const auto& key : keys) {
    if (!root.child(key.first).has("antenna_height_m")) continue;
    if (first_set == nullptr) {
      first_set = &key;
      continue;
    }
    require(*key.second == *first_set->second, key.first + ".antenna_height_m", *key.second,
            "disagrees with " + first_set->first + ".antenna_height_m = " + config_value(*first_set->second) +
                ": the receiver's height above the snow is one fact; set it under one key");
  }
  const double height = first_set != nullptr ? *first_set->second : simulation.antenna_height_m;
  for (const auto& key : keys) *key.second = height;
}

}  // namespace sarloc::app
