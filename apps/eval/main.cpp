// sarloc-eval: Monte Carlo evaluation of sarloc's core estimators.
//
//   sarloc-eval avalanche --filter sog|pf|rbpf|rbpf-improved|grid --trials 100 --seed 1 [--config FILE]
//                         [--json FILE] [--trace-csv FILE] [--trace-trial N]
//   sarloc-eval avalanche --compare [--filters sog,rbpf,...] ...: every filter on the same trials
//   sarloc-eval multi-burial --victims 3 --spread 5 [--trials N] [--seed S] [--json FILE]
//                            [--trace-trial N]
//   sarloc-eval firefighter --building FILE --runs N --seed S [--json FILE] [--plot FILE.svg]
//   sarloc-eval ins FILE [--source config/imu/X.yaml] [--loop] [--footprints TRUTH.csv] [--out TRACK.csv]
//                   [--plot F.svg]
//   sarloc-eval plan BUILDING [--html F.html]
//   sarloc-eval detector [--scenario single|nested-pair|together|lockstep-pair|all] [--draws N] [--seed S]
//                        [--json FILE]
//
// Prints a table in the layout of seed 000, Table I, plus timing and NEES consistency, and the
// same figures as JSON. Exit codes (sarloc::app::ExitCode): 0 all accuracy/consistency targets
// met, 1 ran but a target was missed, 2 usage, 3 config, 4 runtime, 130 interrupted.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "detector_command.hpp"
#include "error_histogram.hpp"
#include "eval_config.hpp"
#include "firefighter_command.hpp"
#include "ins_command.hpp"
#include "plan_command.hpp"
#include "sarloc/app/command_line.hpp"
#include "sarloc/app/evaluation_json.hpp"
#include "sarloc/app/exit_codes.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/progress_bar.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/avalanche/multi_burial.hpp"
#include "sarloc/core/common/errors.hpp"
#include "trial_trace.hpp"

namespace {

using sarloc::app::ExitCode;
using sarloc::app::to_int;
namespace av = sarloc::avalanche;

// Targets of the sarloc issue (seed 000 Table I, SOG row); speed is reported, not gated,
// because it depends on the machine.
struct Targets {
  double median_error_m = 0.21;
  double mean_error_m = 0.23;
  double max_error_m = 0.66;
  double mean_steps = 62.0;
};

void print_table(const av::EvaluationSummary& s, unsigned threads) {
  std::printf("\nAvalanche victim localization, filter %s, %s receiver: %u trials, seed %llu, %u threads\n",
              s.filter.c_str(), s.receiver.c_str(), s.trials, static_cast<unsigned long long>(s.seed), threads);
  std::printf("%-28s %10s %10s %10s\n", "", "MAX", "MEAN", "MEDIAN");
  auto row = [](const char* name, const av::Stats& st) {
    std::printf("%-28s %10.2f %10.2f %10.2f\n", name, st.max, st.mean, st.median);
  };
  row("Error (m)", s.error_m);
  row("Initial receiver distance (m)", s.initial_distance_m);
  row("Steps", s.steps);
  if (s.receiver == "realistic") {
    row("Primary-search steps", s.primary_steps);
    row("Samples used", s.measurements);
    std::printf("%-28s %10u   spurious signals %u\n", "Wrong attributions", s.wrong_attributions,
                s.spurious_signals);
  }
  std::printf("%-28s %10u\n", "Not found within budget", s.not_found);
  std::printf("%-28s %10u   (seed 000, Fig. 5: 25 of 100 for its RBPF)\n", "Error > 1 m", s.errors_over_1m);
  std::printf("%-28s %10u   (error > stated 95 %% radius + %.1f m)\n", "False FOUND", s.false_found,
              av::kFalseFoundMarginM);
  std::printf("%-28s %10u\n", "Ended by probe pattern", s.found_by_probe_pattern);
  std::printf("%-28s %10u   (signal lost while wide: primary line walked again)\n", "Re-planned", s.resumed_line);
  std::printf("%-28s median %.3f  p95 %.3f\n", "ms per filter step", s.ms_per_step_median,
              s.ms_per_step_p95);
  std::printf("%-28s mean %.3f  95%% bounds [%.3f, %.3f] over %u trials  %s\n",
              "NEES (position, 3 dof)", s.nees_mean, s.nees_lower, s.nees_upper, s.nees_trials,
              (s.nees_mean >= s.nees_lower && s.nees_mean <= s.nees_upper) ? "inside" : "OUTSIDE");
  std::printf("%-28s %.3f of converged-phase samples inside [chi2_3(0.025), chi2_3(0.975)]\n",
              "NEES fraction", s.nees_fraction_inside_95);
  std::printf("%-28s %.2f s\n", "Wall clock", s.wall_s);
}

bool check_targets(const av::EvaluationSummary& s) {
  const Targets t;
  bool ok = true;
  auto check = [&](bool pass, const std::string& what) {
    std::printf("  [%s] %s\n", pass ? "ok" : "MISSED", what.c_str());
    ok = ok && pass;
  };
  std::printf("Targets (seed 000 Table I, SOG row):\n");
  check(s.error_m.median <= t.median_error_m, "median error <= 0.21 m");
  check(s.error_m.mean <= t.mean_error_m, "mean error <= 0.23 m");
  check(s.error_m.max <= t.max_error_m, "max error <= 0.66 m");
  check(s.steps.mean <= t.mean_steps, "mean steps <= 62");
  check(s.not_found == 0, "every trial found");
  check(s.false_found == 0, "no false FOUND");
  check(s.nees_mean >= s.nees_lower && s.nees_mean <= s.nees_upper,
        "mean NEES inside the 95 % chi-square bounds");
  return ok;
}

// One row group per filter, the same trials: seed 000's Table I plus the failures, the cost
// and the consistency of each.
void print_comparison(const std::vector<av::EvaluationSummary>& all) {
  if (all.empty()) return;
  std::printf("\nFilter comparison, %s receiver: %u trials, seed %llu, the same scenarios and sensor noise for "
              "every filter\n",
              all.front().receiver.c_str(), all.front().trials, static_cast<unsigned long long>(all.front().seed));
  std::printf("%-14s %21s %21s %6s %6s %6s %15s %31s\n", "", "error (m)", "steps", "> 1 m", "not", "false",
              "ms per update", "NEES mean, share inside");
  std::printf("%-14s %6s %6s %7s %6s %6s %7s %6s %6s %6s %7s %7s %31s\n", "filter", "MAX", "MEAN", "MEDIAN", "MAX",
              "MEAN", "MEDIAN", "", "found", "FOUND", "median", "p95", "[95 % bounds of the mean]");
  for (const auto& s : all) {
    std::printf("%-14s %6.2f %6.2f %7.2f %6.0f %6.1f %7.1f %6u %6u %6u %7.3f %7.3f %8.3g %4.2f [%.2f, %.2f] %s\n",
                s.filter.c_str(), s.error_m.max, s.error_m.mean, s.error_m.median, s.steps.max, s.steps.mean,
                s.steps.median, s.errors_over_1m, s.not_found, s.false_found, s.ms_per_step_median,
                s.ms_per_step_p95, s.nees_mean, s.nees_fraction_inside_95, s.nees_lower, s.nees_upper,
                (s.nees_mean >= s.nees_lower && s.nees_mean <= s.nees_upper) ? "inside" : "OUTSIDE");
  }
}

// Issue 17: the improved RBPF has under a quarter of the plain RBPF's failures > 1 m at no
// more cost per update. Speed against the 2 ms of the issue is machine-dependent: reported.
bool check_comparison(const std::vector<av::EvaluationSummary>& all) {
  const av::EvaluationSummary* plain = nullptr;
  const av::EvaluationSummary* improved = nullptr;
  for (const auto& s : all) {
    if (s.filter == "rbpf") plain = &s;
    if (s.filter == "rbpf-improved") improved = &s;
  }
  if (plain == nullptr || improved == nullptr) return true;
  const bool fewer = 4 * improved->errors_over_1m < plain->errors_over_1m ||
                     (plain->errors_over_1m == 0 && improved->errors_over_1m == 0);
  const bool cheaper = improved->ms_per_step_median <= plain->ms_per_step_median * 1.05;
  std::printf("Targets (issue 17):\n  [%s] rbpf-improved errors > 1 m (%u) under a quarter of rbpf's (%u)\n",
              fewer ? "ok" : "MISSED", improved->errors_over_1m, plain->errors_over_1m);
  std::printf("  [%s] rbpf-improved median update %.3f ms <= rbpf's %.3f ms (5 %% timing noise allowed)\n",
              cheaper ? "ok" : "MISSED", improved->ms_per_step_median, plain->ms_per_step_median);
  std::printf("  [%s] rbpf median update %.3f ms <= 2 ms (this machine, %u threads sharing it)\n",
              plain->ms_per_step_median <= 2.0 ? "ok" : "MISSED", plain->ms_per_step_median,
              std::max(1U, std::thread::hardware_concurrency()));
  return fewer && cheaper;
}

void print_multi_burial(const av::MultiBurialSummary& s, const av::EvaluationSummary& single) {
  std::printf("\nMultiple burials, realistic receiver: %u victims within %.1f m, %u trials, seed %llu\n", s.victims,
              s.spread_m, s.trials, static_cast<unsigned long long>(s.seed));
  std::printf("%-34s %u of %u (%.1f %%)\n", "All victims found", s.all_found, s.trials,
              s.trials > 0 ? 100.0 * s.all_found / s.trials : 0.0);
  // Two carriers within one frequency cell can only be told apart by timing and field; a pair in
  // lockstep (pulses overlapping at every pulse for the first kLockstepS) by the field alone.
  constexpr double kLockstepS = 300.0;
  unsigned close = 0, close_found = 0, lockstep = 0, lockstep_found = 0;
  for (const auto& t : s.per_trial) {
    if (t.lockstep_s >= kLockstepS) {
      ++lockstep;
      if (t.all_found) ++lockstep_found;
    }
    if (t.min_carrier_gap_hz >= av::kCarrierCellHz) continue;
    ++close;
    if (t.all_found) ++close_found;
  }
  std::printf("%-34s %u of %u with two carriers < %.0f Hz apart; %u of %u with all further apart\n", "  of which",
              close_found, close, av::kCarrierCellHz, s.all_found - close_found, s.trials - close);
  std::printf("%-34s %u of %u with a pair in lockstep (one carrier cell, every pulse overlapping for %.0f s or more)\n",
              "  of which", lockstep_found, lockstep, kLockstepS);
  std::printf("%-34s %u\n", "Ghosts (FOUND near no victim)", s.ghosts);
  std::printf("%-34s %u\n", "Victims reported twice", s.duplicates);
  std::printf("%-34s %u of %u (%.1f %%, an honest radius leaves 5 %%)   worst error / radius %.2f\n",
              "FOUNDs outside their 95 % radius", s.founds_outside_radius, s.founds,
              s.founds > 0 ? 100.0 * s.founds_outside_radius / s.founds : 0.0, s.worst_found_error_to_radius);
  std::printf("%-34s %u of %u signals LOCATED   trials with any %u   farthest %.1f m from the antenna\n",
              "LOCATED near no victim", s.false_located, s.located_signals, s.trials_with_false_located,
              s.worst_false_located_range_m);
  std::printf("%-34s %u   of another transmitter %u   suspected %u   trials with any %u\n",
              "Repeats retired (same transmitter)", s.repeats_retired, s.repeats_wrong, s.repeats_suspected,
              s.trials_with_repeats);
  std::printf("%-34s %u   trials with any %u\n", "Filters rebuilt after a leap", s.leaps, s.trials_with_leaps);
  std::printf("%-34s %u   trials with any %u\n", "... converged on no transmitter", s.implausible_rebuilds,
              s.trials_with_implausible_rebuilds);
  std::printf("%-34s %u   trials with any %u\n", "FOUNDs withdrawn by their witness", s.withdrawn_founds,
              s.trials_with_withdrawn_founds);
  std::printf("%-34s %u   trials with any %u\n", "FOUNDs waiting for their witness", s.deferred_founds,
              s.trials_with_deferred_founds);
  std::printf("%-34s %u   trials with any %u\n", "Lost, nothing heard: line again", s.line_resumptions,
              s.trials_with_line_resumptions);
  std::printf("%-34s %llu   unattributed pulses %llu\n", "Wrong attributions (pulses)",
              static_cast<unsigned long long>(s.wrong_attributions),
              static_cast<unsigned long long>(s.unattributed_pulses));
  std::printf("%-34s %llu   other tracked %llu   trials with any %u\n", "Samples of two transmitters summed",
              static_cast<unsigned long long>(s.mixed_samples),
              static_cast<unsigned long long>(s.mixed_samples_both_tracked), s.trials_with_mixed_samples);
  std::printf("%-34s %10s %10s %10s\n", "", "MAX", "MEAN", "MEDIAN");
  std::printf("%-34s %10.1f %10.1f %10.1f\n", "Steps (s) to find all", s.steps.max, s.steps.mean, s.steps.median);
  std::printf("%-34s %10.1f %10.1f %10.1f\n", "First LOCATED (m from the antenna)", s.first_located_range_m.max,
              s.first_located_range_m.mean, s.first_located_range_m.median);
  std::printf("%-34s %10.1f %10.1f %10.1f\n", "Distance (m) to find all", s.distance_m.max, s.distance_m.mean,
              s.distance_m.median);
  std::printf("%-34s %10s %10.1f %10.1f   (single burial, same seed and trials, x %u)\n", "N x single-burial steps", "",
              s.victims * single.steps.mean, s.victims * single.steps.median, s.victims);
  std::printf("%-34s %.2f s\n", "Wall clock", s.wall_s);
  // The trials to look at, each traceable with --trace-trial N.
  bool any = false;
  for (const auto& t : s.per_trial) {
    if (t.all_found && t.ghosts == 0 && t.duplicates == 0 && t.false_located == 0) continue;
    if (!any) std::printf("Trials to trace (--trace-trial N):\n");
    any = true;
    std::printf(
        "  trial %3u: found %u of %u, ghosts %u, twice %u, LOCATED near no victim %u (%.1f m away), %u signals, "
        "carriers %.2f Hz apart at least, in lockstep %.0f s, %u samples of two transmitters\n",
        t.index, t.found, s.victims, t.ghosts, t.duplicates, t.false_located, t.worst_false_located_range_m, t.signals,
        t.min_carrier_gap_hz, t.lockstep_s, t.mixed_samples);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sarloc-eval: Monte Carlo evaluation of sarloc estimators"};
  app.set_version_flag("--version", std::string("sarloc-eval ") + SARLOC_VERSION);
  std::string log_level = "info";
  sarloc::app::add_log_level_option(app, log_level);
  app.require_subcommand(1);
  auto* avalanche = app.add_subcommand("avalanche", "avalanche victim localization (seed 000)");
  std::string filter = "sog";
  std::optional<unsigned> trials;
  std::optional<std::uint64_t> seed;
  std::optional<unsigned> threads;
  std::string config_path;
  std::string json_path;
  bool no_target_check = false;
  std::optional<std::uint32_t> trace;
  std::optional<std::string> receiver;
  avalanche->add_option("--filter", filter, "estimator to evaluate (docs/estimation/baselines.md)")
      ->check(CLI::IsMember({"sog", "pf", "rbpf", "rbpf-improved", "grid"}))
      ->capture_default_str();
  bool compare = false;
  std::vector<std::string> compare_filters;
  avalanche->add_flag("--compare", compare, "run every filter (or --filters) on the very same trials, one table");
  avalanche->add_option("--filters", compare_filters, "with --compare: the filters to run, in order (default all)")
      ->delimiter(',')
      ->check(CLI::IsMember({"sog", "pf", "rbpf", "rbpf-improved", "grid"}));
  std::string plot_path;
  avalanche->add_option("--plot", plot_path, "with --compare: the error histograms (seed 000 Figs. 4-5) as SVG");
  avalanche->add_option("--receiver", receiver,
                        "receiver model: realistic (pulses, sign unknown, unequal antennas; default) or ideal "
                        "(seed 000)")
      ->check(CLI::IsMember({"realistic", "ideal"}));
  avalanche->add_option("--trials", trials, "number of Monte Carlo trials (default: config)");
  avalanche->add_option("--seed", seed, "evaluation seed (default: config)");
  avalanche->add_option("--threads", threads, "worker threads, 0 = all cores (default: config)");
  avalanche->add_option("-c,--config", config_path, "YAML config (config/eval/avalanche.yaml)")
      ->check(CLI::ExistingFile);
  avalanche->add_option("--json", json_path, "write the summary as JSON to this file");
  avalanche->add_option("--trace-trial", trace, "print one trial step by step and exit");
  std::string trace_csv_path;
  avalanche->add_option("--trace-csv", trace_csv_path,
                        "write every step of every trial (truth, measurement, posterior) as CSV");
  avalanche->add_flag("--no-target-check", no_target_check,
                      "exit 0 even when an accuracy/consistency target is missed");
  auto* multi = app.add_subcommand("multi-burial", "several transmitters within a few metres, realistic receiver");
  av::MultiBurialSetup multi_setup;
  std::string multi_config;
  std::optional<unsigned> multi_trials;
  std::optional<std::uint64_t> multi_seed;
  multi->add_option("--victims", multi_setup.victims, "buried transmitters")->capture_default_str();
  multi->add_option("--spread", multi_setup.spread_m, "every victim within this of every other (m)")
      ->capture_default_str();
  multi->add_option("--period-spread", multi_setup.period_spread,
                    "periods within +- this fraction of a common one (pulses overlap for long stretches)")
      ->capture_default_str();
  multi->add_option("--trials", multi_trials, "Monte Carlo trials (default 100)");
  multi->add_option("--seed", multi_seed, "evaluation seed (default: config)");
  double found_witness_window_s = multi_setup.rescuer.found_witness_window_s;
  multi->add_option("--found-witness-window", found_witness_window_s,
                    "seconds of latest samples a FOUND's witness filter is built from (0: no witness)")
      ->capture_default_str();
  multi->add_option("-c,--config", multi_config, "YAML config (simulation:, sog:, search:, evaluation:)")
      ->check(CLI::ExistingFile);
  std::string multi_json;
  multi->add_option("--json", multi_json, "write the summary and every trial as JSON to this file");
  std::optional<std::uint32_t> multi_trace;
  multi->add_option("--trace-trial", multi_trace, "print one trial step by step and exit");
  sarloc::eval::FirefighterOptions firefighter_options;
  auto* firefighter = sarloc::eval::add_firefighter_command(app, firefighter_options);
  sarloc::eval::DetectorOptions detector_options;
  auto* detector = sarloc::eval::add_detector_command(app, detector_options);
  sarloc::eval::InsOptions ins_options;
  auto* ins = sarloc::eval::add_ins_command(app, ins_options);
  sarloc::eval::PlanOptions plan_options;
  auto* plan = sarloc::eval::add_plan_command(app, plan_options);
  if (auto code = sarloc::app::parse_command_line(app, argc, argv)) return *code;
  try {
    sarloc::app::setup_logging(log_level, "sarloc-eval");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sarloc-eval: --log-level %s: %s\n", log_level.c_str(), e.what());
    return to_int(ExitCode::kUsage);
  }
  sarloc::app::install_shutdown_handlers();

  if (firefighter->parsed()) return sarloc::eval::run_firefighter_command(firefighter_options);
  if (detector->parsed()) return sarloc::eval::run_detector_command(detector_options);
  if (ins->parsed()) return sarloc::eval::run_ins_command(ins_options);
  if (plan->parsed()) return sarloc::eval::run_plan_command(plan_options);
  if (multi->parsed()) {
    av::EvaluationSetup base;
    try {
      if (!multi_config.empty()) sarloc::eval::load_avalanche_config(multi_config, base);
      const double period_spread = multi_setup.period_spread;
      multi_setup = sarloc::eval::multi_burial_setup(base, multi_setup.victims, multi_setup.spread_m, multi_trials.value_or(100));
      multi_setup.period_spread = period_spread;
      multi_setup.rescuer.found_witness_window_s = found_witness_window_s;
      if (multi_seed) multi_setup.evaluation.seed = *multi_seed;
      multi_setup.validate();
    } catch (const sarloc::Error& e) {
      spdlog::error("configuration: {}", e.what());
      return to_int(ExitCode::kConfig);
    }
    if (multi_trace) {
      const av::MultiBurialTraceObserver printer = sarloc::eval::multi_burial_trace_printer();
      const av::MultiBurialTrial t = av::run_multi_burial_trial(multi_setup, *multi_trace, &printer);
      std::printf("trial %u: found %u of %u in %u steps, %.1f m; ghosts %u, reported twice %u\n", t.index, t.found,
                  multi_setup.victims, t.steps, t.distance_m, t.ghosts, t.duplicates);
      return to_int(ExitCode::kOk);
    }
    av::MultiBurialSummary ms;
    av::EvaluationSummary single;
    try {
      sarloc::app::ProgressBar bar("trials", multi_setup.evaluation.trials);
      ms = av::run_multi_burial(multi_setup, [&bar] { bar.tick(); },
                                [] { return sarloc::app::shutdown_requested(); });
      bar.finish();
      // The reference: one victim at a time, same configuration, seed and number of trials.
      av::EvaluationSetup one = base;
      one.evaluation = multi_setup.evaluation;
      one.evaluation.step_budget = base.evaluation.step_budget;
      single = av::run_evaluation(one, {}, [] { return sarloc::app::shutdown_requested(); });
    } catch (const std::exception& e) {
      spdlog::error("evaluation failed: {}", e.what());
      return to_int(ExitCode::kRuntime);
    }
    if (sarloc::app::shutdown_requested()) return to_int(ExitCode::kInterrupted);
    print_multi_burial(ms, single);
    if (!multi_json.empty()) {
      try {
        sarloc::app::write_json_file(multi_json, sarloc::app::to_json(ms));
      } catch (const std::exception& e) {
        spdlog::error("--json {}: {}", multi_json, e.what());
        return to_int(ExitCode::kRuntime);
      }
    }
    const bool ok = ms.all_found * 100 >= 98 * ms.trials && ms.ghosts == 0 && ms.duplicates == 0;
    std::printf("Targets (issue 12): [%s] >= 98 %% find every victim, no ghost, no victim reported twice\n",
                ok ? "ok" : "MISSED");
    return ok ? to_int(ExitCode::kOk) : to_int(ExitCode::kFailure);
  }

  av::EvaluationSetup setup;
  try {
    if (!config_path.empty()) sarloc::eval::load_avalanche_config(config_path, setup);
    if (receiver) setup.simulation.receiver.kind = av::parse_receiver_kind(*receiver, "--receiver");
    setup.filter = av::parse_filter_kind(filter, "--filter");
    if (trials) setup.evaluation.trials = *trials;
    if (seed) setup.evaluation.seed = *seed;
    if (threads) setup.evaluation.threads = *threads;
    setup.validate();
  } catch (const sarloc::ConfigError& e) {
    spdlog::error("configuration: {}", e.what());
    return to_int(ExitCode::kConfig);
  } catch (const sarloc::Error& e) {
    spdlog::error("configuration: {}", e.what());
    return to_int(ExitCode::kConfig);
  }

  if (trace) {
    av::run_trial(setup, *trace, sarloc::eval::print_trace_step);
    return to_int(ExitCode::kOk);
  }
  if (compare) {
    std::vector<av::FilterKind> kinds;
    for (const auto& name : compare_filters) kinds.push_back(av::parse_filter_kind(name, "--filters"));
    if (kinds.empty()) kinds.assign(std::begin(av::kAllFilterKinds), std::end(av::kAllFilterKinds));
    std::vector<av::EvaluationSummary> all;
    for (av::FilterKind k : kinds) {
      setup.filter = k;
      spdlog::info("comparison: filter {}, {} trials, seed {}", av::to_string(k), setup.evaluation.trials,
                   setup.evaluation.seed);
      try {
        sarloc::app::ProgressBar bar(av::to_string(k), setup.evaluation.trials);
        all.push_back(av::run_evaluation(setup, [&bar] { bar.tick(); },
                                         [] { return sarloc::app::shutdown_requested(); }));
        bar.finish();
      } catch (const std::exception& e) {
        spdlog::error("evaluation of {} failed: {}", av::to_string(k), e.what());
        return to_int(ExitCode::kRuntime);
      }
      if (all.back().cancelled) return to_int(ExitCode::kInterrupted);
    }
    print_comparison(all);
    if (!plot_path.empty()) {
      std::ofstream out(plot_path);
      out << sarloc::eval::error_histogram_svg(all);
      if (!out.flush()) {
        spdlog::error("--plot {}: cannot write", plot_path);
        return to_int(ExitCode::kRuntime);
      }
    }
    if (!json_path.empty()) {
      nlohmann::json j;
      j["receiver"] = all.front().receiver;
      j["trials"] = all.front().trials;
      j["seed"] = all.front().seed;
      j["hardware_threads"] = std::thread::hardware_concurrency();
      j["filters"] = nlohmann::json::array();
      for (const auto& s : all) j["filters"].push_back(sarloc::app::to_json(s));
      try {
        sarloc::app::write_json_file(json_path, j);
      } catch (const std::exception& e) {
        spdlog::error("--json: {}", e.what());
        return to_int(ExitCode::kRuntime);
      }
    }
    const bool ok = check_comparison(all);
    return (ok || no_target_check) ? to_int(ExitCode::kOk) : to_int(ExitCode::kFailure);
  }
  std::optional<sarloc::eval::TraceCsv> trace_csv;
  std::ofstream trace_out;
  if (!trace_csv_path.empty()) {
    trace_out.open(trace_csv_path);
    if (!trace_out) {
      spdlog::error("cannot write --trace-csv {}", trace_csv_path);
      return to_int(ExitCode::kRuntime);
    }
    trace_csv.emplace(setup.evaluation.trials);
  }
  unsigned used_threads = setup.evaluation.threads;
  if (used_threads == 0) used_threads = std::max(1U, std::thread::hardware_concurrency());
  spdlog::info("avalanche evaluation: filter {}, {} trials, seed {}, {} threads", filter,
               setup.evaluation.trials, setup.evaluation.seed, used_threads);
  av::EvaluationSummary summary;
  try {
    sarloc::app::ProgressBar bar("trials", setup.evaluation.trials);
    av::StepObserver observer;
    if (trace_csv) observer = [&trace_csv](const av::TrialStep& s) { trace_csv->add(s); };
    summary = av::run_evaluation(setup, [&bar] { bar.tick(); },
                                 [] { return sarloc::app::shutdown_requested(); }, observer);
    bar.finish();
  } catch (const std::exception& e) {
    spdlog::error("evaluation failed: {}", e.what());
    return to_int(ExitCode::kRuntime);
  }
  if (summary.cancelled) {
    spdlog::warn("interrupted after {} trials", summary.trials);
    return to_int(ExitCode::kInterrupted);
  }
  print_table(summary, std::min(used_threads, setup.evaluation.trials));
  if (!json_path.empty()) {
    try {
      sarloc::app::write_json_file(json_path, sarloc::app::to_json(summary));
    } catch (const std::exception& e) {
      spdlog::error("--json: {}", e.what());
      return to_int(ExitCode::kRuntime);
    }
  }
  if (trace_csv) {
    trace_csv->write(trace_out);
    if (!trace_out.flush()) {
      spdlog::error("write to --trace-csv {} failed", trace_csv_path);
      return to_int(ExitCode::kRuntime);
    }
  }
  const bool ok = check_targets(summary);
  return (ok || no_target_check) ? to_int(ExitCode::kOk) : to_int(ExitCode::kFailure);
}
