#include "firefighter_command.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <thread>

#include "eval_config.hpp"
#include "rmse_plot.hpp"
#include "sarloc/app/exit_codes.hpp"
#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/app/evaluation_json.hpp"
#include "sarloc/app/progress_bar.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::eval {
namespace {

namespace ff = sarloc::firefighter;
using app::ExitCode;
using app::to_int;

const ff::VariantSummary* find(const ff::FirefighterSummary& s, const std::string& name) {
  for (const auto& v : s.variants) {
    if (v.variant.name == name) return &v;
  }
  return nullptr;
}

void print_summary(const ff::FirefighterSummary& s, double every_s, unsigned threads) {
  std::printf("\nFirefighter localization (seed 004), building %s (%.0f m2 navigable, %zu search patterns): "
              "%u runs (teams of two, %u firefighters), %.0f s each, seed %llu, %u threads\n",
              s.building.c_str(), s.area_m2, s.pattern_windows, s.runs, s.members, s.duration_s,
              static_cast<unsigned long long>(s.seed), threads);
  std::printf("ZUPT INS drift (horizontal, %% of distance walked, median walk %.0f m): median %.2f %%, p95 %.2f %%\n",
              s.distance_median_m, s.ins_drift_median, s.ins_drift_p95);
  std::printf("Firefighters who set foot on each floor:");
  for (std::size_t f = 0; f < s.members_on_floor.size(); ++f) std::printf(" %zu: %u", f, s.members_on_floor[f]);
  std::printf("\n");
  std::printf("Pattern comparison against every window: median %.1f ms (every 4th comparison of each walk)\n\n",
              s.ms_per_comparison_median);
  std::printf("%-30s", "RMSE (m) at t (s)");
  if (!s.variants.empty()) {
    for (std::size_t j = 0; j < s.variants.front().rmse_at_s.size(); ++j) std::printf(" %5.0f", every_s * (j + 1));
  }
  std::printf(" | final overall conv. wrong conf. c.wrong | ms/upd   cmp  mean particles | NEES end [95 %% bounds] (n)\n");
  for (const auto& v : s.variants) {
    std::printf("%-30s", v.variant.name.c_str());
    for (double r : v.rmse_at_s) std::printf(" %5.2f", r);
    std::printf(" | %5.2f %7.2f %5.2f %5.3f %5.2f %7.3f | %6.3f %5.1f %5.2f %9.0f | ", v.final_rmse_m, v.overall_rmse_m,
                v.converged_fraction, v.converged_wrong_fraction, v.confirmed_share, v.confirmed_wrong_fraction,
                v.ms_per_update_amortised,
                v.ms_per_comparison_median, v.ms_per_update_mean, v.particles_mean);
    if (v.nees_members > 0) {
      std::printf("%.2f [%.2f, %.2f] (%u) %s\n", v.nees_mean, v.nees_lower, v.nees_upper, v.nees_members,
                  v.nees_mean >= v.nees_lower && v.nees_mean <= v.nees_upper ? "inside" : "OUTSIDE");
    } else {
      std::printf("-\n");
    }
  }
  std::printf("(conv.: fraction converged within 2 m at the end; wrong: of the estimates flagged converged, the share "
              "whose truth is outside their own 99 %% ellipse; conf.: of those, the share also confirmed (converged 10 s, the weight from an entry, no map error since the start); c.wrong: of the confirmed, the share outside their 99 %% ellipse; ms/upd: median filter step + this row's pattern comparisons spread over the 2 Hz updates; "
              "cmp: median comparison of this row, restricted to the windows its particles can use once concentrated; mean: "
              "mean filter step; particles: mean count)\n");
  for (const auto& v : s.variants) {
    if (v.ambiguous_share > 0.0) {
      std::printf(
          "%s: ambiguous between 2-4 places in %.1f %% of the estimates; truth in none of their 99 %% ellipses in %.1f "
          "%% of those\n",
          v.variant.name.c_str(), 100.0 * v.ambiguous_share, 100.0 * v.ambiguous_wrong_fraction);
    }
  }
  for (const auto& v : s.variants) {
    std::printf(
        "%s: map-error flag raised %.1f times per hour of walking on the right plan (false alarms), up in "
        "%.1f %% of the estimates\n",
        v.variant.name.c_str(), v.false_map_errors_per_hour, 100.0 * v.false_map_error_share);
  }
  std::printf("Wall clock %.1f s\n", s.wall_s);
}

void print_map_error(const ff::MapErrorExperiment& m) {
  std::printf("\nMap-error experiment (seed 004 section V-E): door '%s' moved %.1f m along its wall in the map only; "
              "default filter, known initial state\n",
              m.door.c_str(), m.shift_m);
  std::printf("%8s %12s %10s %10s %12s\n", "t (s)", "var (m2)", "error (m)", "converged", "map error");
  double next = 0.0;
  for (const auto& s : m.timeline) {
    if (s.t + 1e-9 < next) continue;
    next += 10.0;
    std::printf("%8.0f %12.2f %10.2f %10s %12s\n", s.t, s.variance_m2, s.error_m, s.converged ? "yes" : "no",
                s.map_error_suspected ? "RAISED" : "-");
  }
  std::printf("flag raised: %s; recovered (at the end: converged, flag cleared, within 2 m): %s; "
              "cleared while converged more than 2 m off: %.1f s\n",
              m.raised ? "yes" : "no", m.recovered ? "yes" : "no", m.cleared_while_off_s);
}

// `--rows`: names of standard_variants(), or "default" for the configured default's two rows.
std::vector<ff::FilterVariant> chosen_rows(const std::vector<std::string>& rows, const ff::MapFilterConfig& filter) {
  const auto all = ff::standard_variants();
  if (rows.empty()) return all;
  std::vector<std::string> names;
  for (const std::string& name : rows) {
    if (name == "default") {
      names.push_back(ff::variant_name(true, filter.pseudo_observations, filter.resampling));
      names.push_back(ff::variant_name(false, filter.pseudo_observations, filter.resampling));
    } else {
      names.push_back(name);
    }
  }
  std::vector<ff::FilterVariant> out;
  for (const std::string& name : names) {
    const auto it = std::find_if(all.begin(), all.end(), [&](const ff::FilterVariant& v) { return v.name == name; });
    if (it == all.end()) {
      std::string known;
      for (const auto& v : all) known += (known.empty() ? "" : ", ") + v.name;
      throw ConfigError("--rows: unknown row '" + name + "' (rows: default, " + known + ")");
    }
    if (std::none_of(out.begin(), out.end(), [&](const ff::FilterVariant& v) { return v.name == name; })) out.push_back(*it);
  }
  return out;
}

bool check_targets(const ff::FirefighterSummary& s, const ff::MapFilterConfig& filter, double every_s) {
  bool ok = true;
  auto check = [&](bool pass, const std::string& what) {
    std::printf("  [%s] %s\n", pass ? "ok" : "MISSED", what.c_str());
    ok = ok && pass;
  };
  // The rows of the configured default (filter.pseudo_observations, filter.resampling).
  const std::string known_default = ff::variant_name(true, filter.pseudo_observations, filter.resampling);
  const std::string unknown_default = ff::variant_name(false, filter.pseudo_observations, filter.resampling);
  std::printf("\nTargets (issue 13; the default configuration is the rows %s and %s):\n", known_default.c_str(),
              unknown_default.c_str());
  check(s.ins_drift_median <= 1.0, "INS drift median <= 1 % of the distance walked");
  check(s.ins_drift_p95 <= 2.0, "INS drift p95 <= 2 %");
  if (const auto* v = find(s, unknown_default)) {
    bool from150 = true;
    for (std::size_t j = 0; j < v->rmse_at_s.size(); ++j) {
      if (every_s * (j + 1) >= 150.0 - 1e-9) from150 = from150 && v->rmse_at_s[j] <= 1.0;
    }
    check(from150, "unknown initial state, default: RMSE <= 1.0 m from 150 s on");
  }
  if (const auto* v = find(s, known_default)) {
    bool all = true;
    for (double r : v->rmse_at_s) all = all && r <= 1.0;
    check(all, "known initial state, default: RMSE <= 1.0 m throughout");
  }
  for (const bool known : {true, false}) {
    const auto* d = find(s, known ? known_default : unknown_default);
    const auto* w = find(s, ff::variant_name(known, true, ff::PseudoResampling::kNever));
    if (d && w) {
      check(d->overall_rmse_m <= w->overall_rmse_m + 0.05,
            std::string(known ? "known" : "unknown") + ": default never worse than weights-only (overall RMSE, 5 cm tolerance)");
    }
  }
  if (const auto* v = find(s, known_default)) {
    char what[160];
    std::snprintf(what, sizeof what, "one filter update, comparisons amortised: <= 1 ms median (known start, %.0f particles on average)",
                  v->particles_mean);
    check(v->ms_per_update_amortised <= 1.0, what);
  }
  check(s.ms_per_comparison_median <= 100.0, "one pattern comparison <= 100 ms");
  // Never a false position: an honest 99 % ellipse leaves about 1 % of the truths outside.
  for (const auto& name : {known_default, unknown_default}) {
    if (const auto* v = find(s, name)) {
      check(v->confirmed_wrong_fraction <= 0.02, name + ": confirmed positions, at most 2 % outside their own 99 % ellipse");
      // What a commander sees first (issue 65): converged is claimed as a place too.
      check(v->converged_wrong_fraction <= 0.02,
            name + ": converged positions, at most 2 % outside their own 99 % ellipse");
    }
  }
  return ok;
}

}  // namespace

CLI::App* add_firefighter_command(CLI::App& app, FirefighterOptions& o) {
  auto* cmd = app.add_subcommand("firefighter", "map-aided firefighter localization (seed 004)");
  cmd->add_option("--building", o.building, "floor plan (config/buildings/*.yaml, or an IMDF directory *.imdf/)")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("-c,--config", o.config_path, "YAML config (config/eval/firefighter.yaml)")->check(CLI::ExistingFile);
  cmd->add_option("--runs", o.runs, "simulated team searches (default: config)");
  cmd->add_option("--seed", o.seed, "evaluation seed (default: config)");
  cmd->add_option("--threads", o.threads, "worker threads, 0 = all cores (default: config)");
  cmd->add_option("--json", o.json_path, "write the summary as JSON to this file");
  cmd->add_option("--plot", o.plot_path, "draw the RMSE curves to this SVG file");
  cmd->add_option("--map-error-door", o.map_error_door, "door moved in the map-error experiment (default: chosen)");
  cmd->add_option("--map-error-shift", o.map_error_shift_m, "how far it moves along its wall (m)")->capture_default_str();
  cmd->add_option("--rows", o.rows,
                  "comma-separated configurations to run (e.g. known/weights,unknown/no-pseudo), or 'default' for the "
                  "configured default's two rows (default: all eight)")
      ->delimiter(',');
  cmd->add_flag("--no-map-error", o.no_map_error, "skip the map-error experiment");
  cmd->add_flag("--no-target-check", o.no_target_check, "exit 0 even when a target is missed");
  return cmd;
}

int run_firefighter_command(const FirefighterOptions& o) {
  ff::FloorPlan plan;
  ff::FirefighterEvalConfig config;
  std::vector<ff::FilterVariant> rows;
  try {
    plan = app::load_floor_plan(o.building);
    if (!o.config_path.empty()) load_firefighter_config(o.config_path, config);
    if (o.runs) config.runs = *o.runs;
    if (o.seed) config.seed = *o.seed;
    if (o.threads) config.threads = *o.threads;
    config.validate();
    rows = chosen_rows(o.rows, config.filter);
  } catch (const Error& e) {
    spdlog::error("configuration: {}", e.what());
    return to_int(ExitCode::kConfig);
  }
  unsigned threads = config.threads == 0 ? std::max(1U, std::thread::hardware_concurrency()) : config.threads;
  spdlog::info("firefighter evaluation: building {}, {} runs, seed {}, {} threads", plan.name, config.runs,
               config.seed, threads);
  ff::FirefighterSummary summary;
  ff::MapErrorExperiment map_error;
  try {
    ff::FirefighterEvaluation evaluation(plan, config, rows);
    app::ProgressBar bar("runs", config.runs);
    summary = evaluation.run([&bar] { bar.tick(); }, [] { return app::shutdown_requested(); });
    bar.finish();
    if (summary.cancelled) return to_int(ExitCode::kInterrupted);
    if (!o.no_map_error) map_error = evaluation.map_error_experiment(o.map_error_door, o.map_error_shift_m);
  } catch (const ConfigError& e) {
    spdlog::error("configuration: {}", e.what());
    return to_int(ExitCode::kConfig);
  } catch (const std::exception& e) {
    spdlog::error("evaluation failed: {}", e.what());
    return to_int(ExitCode::kRuntime);
  }
  print_summary(summary, config.rmse_every_s, std::min(threads, config.runs));
  if (!o.no_map_error) print_map_error(map_error);
  try {
    if (!o.json_path.empty()) {
      app::write_json_file(o.json_path, app::to_json(summary, config.rmse_every_s, o.no_map_error ? nullptr : &map_error));
    }
    if (!o.plot_path.empty()) {
      std::ofstream out(o.plot_path);
      out << rmse_plot_svg(summary, config.rmse_every_s);
      if (!out.flush()) throw std::runtime_error("cannot write --plot " + o.plot_path);
    }
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return to_int(ExitCode::kRuntime);
  }
  const bool ok = check_targets(summary, config.filter, config.rmse_every_s);
  return (ok || o.no_target_check) ? to_int(ExitCode::kOk) : to_int(ExitCode::kFailure);
}

}  // namespace sarloc::eval
