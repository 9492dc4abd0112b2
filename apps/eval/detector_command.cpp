#include "detector_command.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "sarloc/app/exit_codes.hpp"
#include "sarloc/app/progress_bar.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/avalanche/detector_bench.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/statistics.hpp"

namespace sarloc::eval {
namespace {

namespace av = sarloc::avalanche;
using app::ExitCode;
using sarloc::percentile;
using app::to_int;

}  // namespace

CLI::App* add_detector_command(CLI::App& app, DetectorOptions& options) {
  auto* cmd = app.add_subcommand("detector", "the pulse detector alone on overlapping pulses of known truth");
  cmd->add_option("--scenario", options.scenario, "single (the control), nested-pair, together, lockstep-pair or all")
      ->check(CLI::IsMember({"single", "nested-pair", "together", "lockstep-pair", "all"}))
      ->capture_default_str();
  cmd->add_option("--draws", options.draws, "windows per scenario")->capture_default_str();
  cmd->add_option("--seed", options.seed, "random seed")->capture_default_str();
  cmd->add_option("--json", options.json_path, "write the figures as JSON to this file");
  return cmd;
}

int run_detector_command(const DetectorOptions& options) {
  std::vector<av::DetectorScenario> scenarios;
  for (av::DetectorScenario s : {av::DetectorScenario::kSingle, av::DetectorScenario::kNestedPair, av::DetectorScenario::kTogether,
                                   av::DetectorScenario::kLockstepPair})
    if (options.scenario == "all" || options.scenario == av::to_string(s)) scenarios.push_back(s);
  nlohmann::json out = nlohmann::json::array();
  std::printf("Pulse detector alone, %u windows per scenario, seed %llu (docs/estimation/avalanche.md, \"Detector bench\")\n", options.draws,
              static_cast<unsigned long long>(options.seed));
  std::printf("Amplitude error of the matched pulses let through to the tracks: in units of their stated noise (an\n"
              "honest noise gives about 1) and relative to the transmitter's field (the filter allows 5 %% plus calibration).\n\n");
  std::printf("%-12s %7s %8s %13s %8s | %-26s %5s %5s | %-21s %5s | %8s %6s\n", "scenario", "pulses", "spurious",
              "let through", "matched", "sigma: median / p90 / max", ">10", ">50", "relative: median / p90", ">5 %",
              "|df| med", "edges");
  for (av::DetectorScenario scenario : scenarios) {
    av::DetectorBenchSetup setup;
    setup.scenario = scenario;
    setup.draws = options.draws;
    setup.seed = options.seed;
    av::DetectorBenchResult r;
    try {
      app::ProgressBar bar(av::to_string(scenario), setup.draws);
      r = av::run_detector_bench(setup, [&bar] { bar.tick(); }, [] { return app::shutdown_requested(); });
      bar.finish();
    } catch (const ConfigError& e) {
      spdlog::error("configuration: {}", e.what());
      return to_int(ExitCode::kConfig);
    }
    if (app::shutdown_requested()) return to_int(ExitCode::kInterrupted);
    const auto& e = r.error_sigma;
    const auto& rel = r.error_relative;
    std::printf("%-12s %7u %8u %7u (%3u) %8zu | %7.2f / %6.2f / %7.1f %5u %5u | %8.3f / %8.3f %5u | %5.3f Hz %4.0f %%\n",
                av::to_string(scenario), r.pulses, r.spurious, r.let_through, r.let_through_spurious, e.size(),
                percentile(e, 0.5), percentile(e, 0.9), e.empty() ? 0.0 : e.back(), r.beyond_10_sigma, r.beyond_50_sigma,
                percentile(rel, 0.5), percentile(rel, 0.9), r.beyond_5_percent, r.carrier_error_median_hz,
                100.0 * r.edges_exact_share);
    out.push_back({{"scenario", av::to_string(scenario)},
                   {"draws", r.draws},
                   {"transmitters", r.transmitters},
                   {"pulses", r.pulses},
                   {"spurious", r.spurious},
                   {"let_through", r.let_through},
                   {"let_through_spurious", r.let_through_spurious},
                   {"matched", e.size()},
                   {"error_sigma", {{"median", percentile(e, 0.5)}, {"p90", percentile(e, 0.9)}, {"max", e.empty() ? 0.0 : e.back()}}},
                   {"beyond_10_sigma", r.beyond_10_sigma},
                   {"beyond_50_sigma", r.beyond_50_sigma},
                   {"error_relative", {{"median", percentile(rel, 0.5)}, {"p90", percentile(rel, 0.9)}, {"max", rel.empty() ? 0.0 : rel.back()}}},
                   {"beyond_5_percent", r.beyond_5_percent},
                   {"carrier_error_median_hz", r.carrier_error_median_hz},
                   {"edges_exact_share", r.edges_exact_share}});
  }
  if (!options.json_path.empty()) {
    std::ofstream f(options.json_path);
    if (!(f << out.dump(2) << '\n')) {
      spdlog::error("--json {}: cannot write", options.json_path);
      return to_int(ExitCode::kRuntime);
    }
  }
  return to_int(ExitCode::kOk);
}

}  // namespace sarloc::eval
