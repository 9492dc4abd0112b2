#include "eval_config.hpp"

#include <algorithm>
#include <cmath>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/app/avalanche_yaml.hpp"
#include "sarloc/app/firefighter_yaml.hpp"
#include "sarloc/app/yaml_reader.hpp"

namespace sarloc::eval {
namespace {

using app::YamlReader;

void load(YamlReader root, avalanche::EvaluationSetup& setup) {
  // The estimator's sections mean the same here as in a mission file (avalanche_yaml.hpp).
  app::read_simulation(root.child("simulation"), setup.simulation);
  app::read_sog(root.child("sog"), setup.sog);
  app::hold_one_antenna_height(root, setup.simulation, setup.sog, nullptr);
  app::read_search(root.child("search"), setup.search);
  {
    // The particle-filter baselines (docs/estimation/baselines.md, "Parameters").
    auto r = root.child("particle");
    auto& c = setup.particle;
    r.read("particles", c.particles);
    r.read("resample_ess_fraction", c.resample_ess_fraction);
    r.read("moment_noise_relative", c.moment_noise_relative);
    r.read("improved_particles", c.improved_particles);
    r.read("regularisation_scale", c.regularisation_scale);
    r.read("regularise_below_radius_m", c.regularise_below_radius_m);
    r.read("rebuild_on_divergence", c.rebuild_on_divergence);
    r.expect_done();
  }
  {
    // The grid filter (docs/estimation/baselines.md, "Parameters").
    auto r = root.child("grid");
    auto& c = setup.grid;
    r.read("cell_m", c.cell_m);
    r.read("finest_cell_m", c.finest_cell_m);
    r.read("refine_cells", c.refine_cells);
    r.read("prune_log_weight", c.prune_log_weight);
    r.read("max_cells", c.max_cells);
    r.expect_done();
  }
  {
    auto r = root.child("evaluation");
    auto& c = setup.evaluation;
    r.read("trials", c.trials);
    r.read("seed", c.seed);
    r.read("threads", c.threads);
    r.read("step_budget", c.step_budget);
    r.expect_done();
  }
  root.expect_done();
  setup.validate();
}


// Reads `key` given in degrees (or deg/s, deg/s/sqrt(Hz), deg/h, mg, ug) into SI units. A value
// equal to the default but for the conversion's rounding keeps the default bit for bit: the
// shipped config must reproduce a run without it exactly (a last-bit difference changes a
// simulated walk's random path).
void read_scaled(YamlReader& r, const std::string& key, double& value, double unit) {
  const double shown = value / unit;
  double v = shown;
  r.read(key, v);
  if (std::abs(v - shown) > 1e-12 * std::abs(shown)) value = v * unit;
}

}  // namespace

void read_ins(YamlReader r, firefighter::ZuptInsConfig& n) {
  r.read("alignment_s", n.alignment_s);
  r.read("alignment_min_s", n.alignment_min_s);
  r.read("alignment_bias_s", n.alignment_bias_s);
  r.read("zupt_sigma_mps", n.zupt_sigma_mps);
  r.read("zupt_rotation_lever_m", n.zupt_rotation_lever_m);
  r.read("landing_speed_max_mps", n.landing_speed_max_mps);
  r.read("swing_pause_max_s", n.swing_pause_max_s);
  r.read("swing_max_s", n.swing_max_s);
  read_scaled(r, "zaru_sigma_deg_per_s", n.zaru_sigma_radps, kDeg);
  r.read("zaru_after_s", n.zaru_after_s);
  r.read("level_step_m", n.level_step_m);
  r.read("level_sigma_m", n.level_sigma_m);
  r.read("stride_noise_m2_per_m", n.stride_noise_m2_per_m);
  r.read("detector_window", n.detector_window);
  r.read("detector_sigma_accel", n.detector_sigma_accel);
  read_scaled(r, "detector_sigma_gyro_deg_per_s", n.detector_sigma_gyro, kDeg);
  r.read("detector_threshold", n.detector_threshold);
  r.read("adaptive_stance", n.adaptive_stance);
  r.read("motionless_after_s", n.motionless_after_s);
  r.expect_done();
}

namespace {

void load_firefighter(YamlReader root, firefighter::FirefighterEvalConfig& c) {
  {
    auto r = root.child("walk");
    auto& w = c.walk;
    r.read("duration_s", w.duration_s);
    r.read("standing_s", w.standing_s);
    r.read("speed_min_mps", w.speed_min_mps);
    r.read("speed_max_mps", w.speed_max_mps);
    r.read("crawl_speed_mps", w.crawl_speed_mps);
    r.read("stride_m", w.stride_m);
    r.read("crawl_stride_m", w.crawl_stride_m);
    r.read("stance_fraction", w.stance_fraction);
    r.read("offset_min_m", w.offset_min_m);
    r.read("offset_max_m", w.offset_max_m);
    r.read("stop_per_m", w.stop_per_m);
    r.read("sweep_per_m", w.sweep_per_m);
    r.read("turn_back_per_m", w.turn_back_per_m);
    r.read("crawl_per_m", w.crawl_per_m);
    r.read("skip_room_probability", w.skip_room_probability);
    r.read("follower_delay_s", w.follower_delay_s);
    r.expect_done();
  }
  {
    auto r = root.child("imu");
    auto& m = c.imu;
    constexpr double g = firefighter::kGravity;
    r.read("rate_hz", m.rate_hz);
    read_scaled(r, "accel_noise_density_ug_per_sqrt_hz", m.accel_noise_density, 1e-6 * g);
    read_scaled(r, "accel_bias_instability_mg", m.accel_bias_instability, 1e-3 * g);
    read_scaled(r, "accel_turn_on_bias_mg", m.accel_turn_on_bias, 1e-3 * g);
    r.read("accel_scale_factor", m.accel_scale_factor);
    read_scaled(r, "gyro_noise_density_deg_per_s_sqrt_hz", m.gyro_noise_density, kDeg);
    read_scaled(r, "gyro_bias_instability_deg_per_h", m.gyro_bias_instability, kDeg / 3600.0);
    read_scaled(r, "gyro_turn_on_bias_deg_per_s", m.gyro_turn_on_bias, kDeg);
    r.read("gyro_scale_factor", m.gyro_scale_factor);
    r.read("bias_correlation_time_s", m.bias_correlation_time_s);
    r.expect_done();
  }
  read_ins(root.child("ins"), c.ins);
  {
    auto r = root.child("pattern");
    r.read("grid_spacing_m", c.grid.spacing_m);
    r.read("min_clearance_m", c.grid.min_clearance_m);
    r.read("room_skips", c.grid.room_skips);
    r.read("room_skip_min_nodes", c.grid.room_skip_min_nodes);
    r.read("pattern_length_m", c.pattern.pattern_length_m);
    r.read("compare_every_m", c.pattern.compare_every_m);
    r.read("trajectory_spacing_m", c.pattern.trajectory_spacing_m);
    r.read("pattern_point_spacing_m", c.pattern.pattern_point_spacing_m);
    r.read("icp_iterations", c.pattern.icp_iterations);
    r.read("icp_tolerance_m", c.pattern.icp_tolerance_m);
    r.read("prune_margin_m", c.pattern.prune_margin_m);
    r.expect_done();
  }
  read_map_filter(root.child("filter"), c.filter);
  {
    auto r = root.child("evaluation");
    r.read("runs", c.runs);
    r.read("seed", c.seed);
    r.read("threads", c.threads);
    r.read("odometry_rate_hz", c.odometry_rate_hz);
    r.read("rmse_every_s", c.rmse_every_s);
    r.expect_done();
  }
  root.expect_done();
  try {
    c.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(root.source() + ": " + e.what());
  }
}

}  // namespace

void load_firefighter_config(const std::string& path, firefighter::FirefighterEvalConfig& config) {
  load_firefighter(YamlReader::from_file(path), config);
}

void load_firefighter_config_text(const std::string& text, const std::string& name,
                                  firefighter::FirefighterEvalConfig& config) {
  load_firefighter(YamlReader::from_string(text, name), config);
}

avalanche::MultiBurialSetup multi_burial_setup(const avalanche::EvaluationSetup& base, std::uint32_t victims,
                                               double spread_m, std::uint32_t trials) {
  avalanche::MultiBurialSetup setup;
  setup.victims = victims;
  setup.spread_m = spread_m;
  setup.simulation = base.simulation;  // multi_burial refuses the ideal receiver, naming the key
  setup.rescuer.sog = base.sog;
  setup.rescuer.search = base.search;
  setup.evaluation = base.evaluation;
  setup.evaluation.trials = trials;
  setup.evaluation.step_budget = std::max<std::uint32_t>(base.evaluation.step_budget, 200 * victims);
  return setup;
}

void load_avalanche_config(const std::string& path, avalanche::EvaluationSetup& setup) {
  load(YamlReader::from_file(path), setup);
}

void load_avalanche_config_text(const std::string& text, const std::string& name,
                                avalanche::EvaluationSetup& setup) {
  load(YamlReader::from_string(text, name), setup);
}

}  // namespace sarloc::eval
