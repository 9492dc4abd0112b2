#include "ins_command.hpp"

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "eval_config.hpp"
#include "ins_plot.hpp"
#include "sarloc/app/exit_codes.hpp"
#include "sarloc/app/imu_source_yaml.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/firefighter/imu_source.hpp"
#include "sarloc/core/firefighter/ins_recording.hpp"

namespace sarloc::eval {
namespace {

namespace ff = sarloc::firefighter;
using app::ExitCode;
using app::to_int;

// The shared footprint truth: `# comments`, the header `stride,x_m,y_m`, then one row per
// stride in order from 0 (the start pose).
std::vector<Eigen::Vector2d> read_footprints(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError("--footprints '" + path + "': cannot open");
  std::vector<Eigen::Vector2d> truth;
  std::string line;
  std::size_t n = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line[0] == '#' || line == "\r") continue;
    if (!header) {
      if (line.rfind("stride,x_m,y_m", 0) != 0)
        throw ConfigError(path + ":" + std::to_string(n) + ": header '" + line + "': expected 'stride,x_m,y_m'");
      header = true;
      continue;
    }
    std::stringstream row(line);
    std::string k, x, y;
    std::getline(row, k, ',');
    std::getline(row, x, ',');
    std::getline(row, y, ',');
    char* end_k = nullptr;
    char* end_x = nullptr;
    char* end_y = nullptr;
    const long stride = std::strtol(k.c_str(), &end_k, 10);
    const double vx = std::strtod(x.c_str(), &end_x), vy = std::strtod(y.c_str(), &end_y);
    if (k.empty() || x.empty() || y.empty() || end_x == x.c_str() || end_y == y.c_str() || !std::isfinite(vx) ||
        !std::isfinite(vy) || stride != static_cast<long>(truth.size()))
      throw ConfigError(path + ":" + std::to_string(n) + ": row '" + line + "': expected stride " +
                        std::to_string(truth.size()) + ",x_m,y_m with finite numbers");
    truth.emplace_back(vx, vy);
  }
  if (truth.size() < 2) throw ConfigError(path + ": fewer than two footprints");
  return truth;
}

}  // namespace

CLI::App* add_ins_command(CLI::App& app, InsOptions& options) {
  auto* cmd = app.add_subcommand("ins", "the boot INS on one recorded foot IMU file (docs/estimation/firefighter.md)");
  cmd->add_option("file", options.file, "the recording")->required();
  cmd->add_option("--source", options.source,
                  "its IMU source description (config/imu/*.yaml); default: the sarloc boot IMU CSV")
      ->check(CLI::ExistingFile);
  cmd->add_option("-c,--config", options.config_path,
                  "YAML whose ins: section sets the INS (config/eval/firefighter.yaml's keys; a --source file's stance "
                  "settings win); default: the device's")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--loop", options.loop, "the walk is a closed loop: print the loop-closure error");
  cmd->add_option("--footprints", options.footprints, "footprint truth CSV (stride,x_m,y_m): stride-aligned errors")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", options.out, "write the track: t_s,x_m,y_m,z_m,stationary, every sample after alignment");
  cmd->add_option("--plot", options.plot, "write the top view and height against time as SVG");
  cmd->add_option("--json", options.json_path, "write the figures as JSON");
  return cmd;
}

int run_ins_command(const InsOptions& options) {
  ff::ImuSourceFormat format = ff::sarloc_csv();
  std::vector<ff::ImuSample> samples;
  std::vector<Eigen::Vector2d> truth;
  ff::ImuSourceCounts counts;
  std::vector<std::string> problems;
  double rate_hz = 0.0;
  try {
    if (!options.source.empty()) format = app::load_imu_source(options.source);
    std::ifstream in(options.file);
    if (!in) throw ConfigError(options.file + ": cannot open the recording");
    ff::ImuSourceReader reader(in, options.file, format);
    while (auto s = reader.next()) samples.push_back(*s);
    counts = reader.counts();
    problems = reader.problems();
    rate_hz = reader.rate_hz();
    if (!options.footprints.empty()) truth = read_footprints(options.footprints);
  } catch (const ConfigError& e) {
    spdlog::error("{}", e.what());
    return to_int(ExitCode::kConfig);
  }
  for (const auto& p : problems) spdlog::warn("{}", p);
  if (problems.size() < counts.refused() + counts.clipped && !problems.empty())
    spdlog::warn("... {} more (all counted below)", counts.refused() + counts.clipped - problems.size());

  ff::ZuptInsConfig config;
  config.rate_hz = rate_hz;
  try {
    if (!options.config_path.empty()) read_ins(app::YamlReader::from_file(options.config_path).child("ins"), config);
    ff::apply_declared(format, config);
    config.validate();
  } catch (const ConfigError& e) {
    spdlog::error("{}", e.what());
    return to_int(ExitCode::kConfig);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const ff::InsRecording run = ff::run_ins(samples, config);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::printf("sarloc-eval ins %s (source: %s)\n", options.file.c_str(), format.name.c_str());
  std::printf("  samples         %zu rows read, %zu to the INS at %.1f Hz over %.1f s\n", counts.rows, counts.samples,
              rate_hz, run.duration_s);
  std::printf(
      "  time            %zu repeated time(s) (%s), %zu out of order (dropped), %zu gap(s) (longest %.4f s)\n",
      counts.repeated_time,
      format.repeated_time == ff::RepeatedTimeRule::kInterpolate ? "re-timed between their neighbours" : "dropped",
      counts.out_of_order, counts.gaps, counts.longest_gap_s);
  std::printf("  refused         %zu malformed, %zu invalid flag, %zu beyond range; %zu clipped to the range\n",
              counts.malformed, counts.invalid_flag, counts.over_range, counts.clipped);
  for (const auto& [reason, n] : run.refused) std::printf("  refused by INS  %zu: %s\n", n, reason.c_str());
  nlohmann::json out{{"file", options.file},
                     {"source", format.name},
                     {"rows", counts.rows},
                     {"samples", counts.samples},
                     {"rate_hz", rate_hz},
                     {"repeated_time", counts.repeated_time},
                     {"out_of_order", counts.out_of_order},
                     {"malformed", counts.malformed},
                     {"clipped", counts.clipped},
                     {"gaps", counts.gaps},
                     {"aligned", run.aligned_at_s.has_value()}};
  if (!run.aligned_at_s) {
    std::printf("  alignment       no stillness: not aligned (longest still spell %.2f s, %.2f s needed)\n",
                run.longest_still_s, config.alignment_s);
    out["longest_still_s"] = run.longest_still_s;
  } else {
    constexpr double kToDeg = 180.0 / kPi;
    std::printf("  alignment       at %.2f s: roll %.1f deg, pitch %.1f deg, gyro bias (%.3f, %.3f, %.3f) deg/s\n",
                *run.aligned_at_s, run.roll_rad * kToDeg, run.pitch_rad * kToDeg, run.gyro_bias.x() * kToDeg,
                run.gyro_bias.y() * kToDeg, run.gyro_bias.z() * kToDeg);
    // What a source file would declare (noise:), as the stillest part of the spell shows it.
    std::printf(
        "  noise at rest   accel %.2e m/s^2/sqrt(Hz), gyro %.2e rad/s/sqrt(Hz) (%s); the INS's process noise: %.2e, "
        "%.2e\n",
        run.rest_noise.accel_density, run.rest_noise.gyro_density,
        format.accel_noise_density > 0.0 || format.gyro_noise_density > 0.0 ? "the source declares its own"
                                                                            : "not declared: the MTi-3's",
        config.accel_noise_density, config.gyro_noise_density);
    out["rest_noise"] = {{"accel_density", run.rest_noise.accel_density},
                         {"gyro_density", run.rest_noise.gyro_density}};
    const Eigen::Vector3d end = run.track.empty() ? Eigen::Vector3d::Zero() : run.track.back().p;
    std::printf("  walk            %zu stance phases, %.2f m walked, ends at (%.2f, %.2f, %.2f) m\n",
                run.stances.size(), run.distance_m, end.x(), end.y(), end.z());
    out["aligned_at_s"] = *run.aligned_at_s;
    out["stances"] = run.stances.size();
    out["distance_m"] = run.distance_m;
    out["end_m"] = {end.x(), end.y(), end.z()};
  }
  if (options.loop) {
    if (const auto e = ff::loop_error(run)) {
      std::printf("  loop closure    %.3f m 3-D (%.3f horizontal, %.3f vertical): %.2f %% of the distance\n",
                  e->error_3d_m, e->horizontal_m, e->vertical_m,
                  100.0 * e->error_3d_m / std::max(run.distance_m, 1e-9));
      out["loop"] = {{"error_3d_m", e->error_3d_m}, {"horizontal_m", e->horizontal_m}, {"vertical_m", e->vertical_m}};
    } else {
      std::printf("  loop closure    none: fewer than two stance phases\n");
    }
  }
  double turn_rad = 0.0;
  if (!truth.empty()) {
    if (const auto f = ff::footprint_errors(run, truth)) {
      turn_rad = f->turn_rad;
      const double d = std::max(f->truth_distance_m, 1e-9);
      std::printf(
          "  footprints      %zu strides in the truth, %zu stance phases after the start; %zu compared over %.1f m\n",
          f->strides_truth, f->strides_track, f->compared, f->truth_distance_m);
      std::printf("  stride-aligned  final %.3f m (%.2f %%), rms %.3f m, max %.3f m\n", f->final_m,
                  100.0 * f->final_m / d, f->rms_m, f->max_m);
      std::printf("  rigid-aligned   final %.3f m, rms %.3f m (%.2f %%), max %.3f m\n", f->rigid_final_m,
                  f->rigid_rms_m, 100.0 * f->rigid_rms_m / d, f->rigid_max_m);
      const bool inside = f->stride_nees_mean >= f->stride_nees_lower && f->stride_nees_mean <= f->stride_nees_upper;
      std::printf(
          "  stride NEES     %.2f over %zu strides (%zu of them grouped), 95 %% bounds [%.2f, %.2f] %s; variance "
          "missing %.4f m^2 per m walked\n",
          f->stride_nees_mean, f->stride_pairs, f->stride_groups, f->stride_nees_lower, f->stride_nees_upper,
          inside ? "inside" : "OUTSIDE", f->missing_variance_per_m);
      std::printf("  heading wander  %.2f deg per stride of %.2f m (RMS change of the heading offset)\n",
                  f->heading_wander_rad / kDeg, f->mean_stride_m);
      out["footprints"] = {{"strides_truth", f->strides_truth},
                           {"strides_track", f->strides_track},
                           {"compared", f->compared},
                           {"truth_distance_m", f->truth_distance_m},
                           {"final_m", f->final_m},
                           {"rms_m", f->rms_m},
                           {"max_m", f->max_m},
                           {"rigid_final_m", f->rigid_final_m},
                           {"rigid_rms_m", f->rigid_rms_m},
                           {"rigid_max_m", f->rigid_max_m},
                           {"stride_nees_mean", f->stride_nees_mean},
                           {"stride_nees_lower", f->stride_nees_lower},
                           {"stride_nees_upper", f->stride_nees_upper},
                           {"missing_variance_per_m", f->missing_variance_per_m},
                           {"stride_pairs", f->stride_pairs},
                           {"stride_groups", f->stride_groups},
                           {"heading_wander_deg", f->heading_wander_rad / kDeg},
                           {"mean_stride_m", f->mean_stride_m}};
    } else {
      std::printf("  footprints      none compared: fewer than two stance phases\n");
    }
  }
  std::printf("  speed           %.0f x real time (%.3f s for %.1f s of recording, one core)\n",
              run.duration_s / std::max(wall_s, 1e-9), wall_s, run.duration_s);
  if (!options.out.empty()) {
    std::ofstream f(options.out);
    f << "t_s,x_m,y_m,z_m,stationary\n";
    char line[128];
    for (const auto& p : run.track) {
      std::snprintf(line, sizeof line, "%.6f,%.5f,%.5f,%.5f,%d\n", p.t, p.p.x(), p.p.y(), p.p.z(),
                    p.stationary ? 1 : 0);
      f << line;
    }
    if (!f) {
      spdlog::error("--out {}: cannot write", options.out);
      return to_int(ExitCode::kRuntime);
    }
  }
  if (!options.plot.empty()) {
    std::ofstream f(options.plot);
    if (!(f << ins_plot_svg(run, options.file + " (" + format.name + ")", truth, turn_rad))) {
      spdlog::error("--plot {}: cannot write", options.plot);
      return to_int(ExitCode::kRuntime);
    }
  }
  if (!options.json_path.empty()) {
    std::ofstream f(options.json_path);
    if (!(f << out.dump(2) << '\n')) {
      spdlog::error("--json {}: cannot write", options.json_path);
      return to_int(ExitCode::kRuntime);
    }
  }
  return to_int(run.aligned_at_s ? ExitCode::kOk : ExitCode::kFailure);
}

}  // namespace sarloc::eval
