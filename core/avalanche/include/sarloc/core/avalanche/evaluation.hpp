#pragma once
// Monte Carlo evaluation of a transmitter filter (EvaluationSetup::filter: the SOG filter or a
// baseline) + search controller against the simulator, the reproduction of seed 000, Table I. Trials run in parallel; trial i uses
// derive_seed(seed, i) only, so the figures do not depend on the thread count.
//
// Per trial: measure -> filter.update -> controller.guide -> (stop if found) -> walk -> odometry.
//   error_m            |p_est - p_true| (3-D, G_k) when "found" is declared (or at the budget)
//   initial_distance_m horizontal rescuer -> transmitter distance when first heard
//   steps              steps walked from the first sample heard (the first one included); with
//                      the ideal receiver every step has a sample, with the realistic one a
//                      step hears 0-2 pulses of the transmitter (period 0.7-1.3 s)
//   ms per step        wall time of the filter update for every sample of every trial
//   NEES               position part of the mixture (eq. (18)) against the truth, 3 dof, over the
//                      converged phase (steps whose mixture 95 % radius <= sog.converged_radius_m)
//   false FOUND        found, but farther from the victim than the 95 % radius stated with the
//                      estimate + kFalseFoundMarginM: a FOUND the rescuer could not trust
//
//   EvaluationSetup setup;  setup.evaluation.trials = 100;
//   EvaluationSummary s = run_evaluation(setup, [&] { bar.tick(); });
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sarloc/core/avalanche/found_victim.hpp"
#include "sarloc/core/avalanche/search_controller.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/avalanche/grid_filter.hpp"
#include "sarloc/core/avalanche/particle_filter.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/statistics.hpp"

namespace sarloc::avalanche {

struct EvaluationConfig {
  std::uint32_t trials = 100;       ///< seed 000, section V
  std::uint64_t seed = 1;
  std::uint32_t threads = 0;        ///< 0 = std::thread::hardware_concurrency()
  std::uint32_t step_budget = 200;  ///< a trial not found after this many steps is "not found"

  /// Throws ConfigError "evaluation.<key> = value: rule".
  void validate() const;
};

struct EvaluationSetup {
  SimulationConfig simulation;
  FilterKind filter = FilterKind::kSog;  ///< the filter the trials run (docs/estimation/baselines.md)
  SogConfig sog;                         ///< the SOG filter, and the ring and noise model every filter shares
  ParticleFilterConfig particle;         ///< pf, rbpf, rbpf-improved
  GridFilterConfig grid;                 ///< grid
  SearchConfig search;
  EvaluationConfig evaluation;
  void validate() const;
};

struct TrialResult {
  std::uint32_t index = 0;
  bool found = false;
  double error_m = 0.0;
  double horizontal_error_m = 0.0;
  double initial_distance_m = 0.0;
  std::uint32_t steps = 0;
  std::vector<double> step_ms;       ///< SogFilter::process wall time per step
  std::vector<double> nees;          ///< position NEES per converged step
  double final_nees = 0.0;
  std::uint32_t final_components = 0;
  std::uint32_t flux_line_steps = 0;   ///< steps guided in kOpening mode
  std::uint32_t first_converged_step = 0;  ///< first step with a converged mixture (0 = never)
  std::uint32_t reinitialisations = 0;     ///< SogStepResult::reinitialised count
  double radius95_m = 0.0;        ///< 3-D 95 % radius stated with the final estimate
  bool false_found = false;       ///< found and error_m > radius95_m + kFalseFoundMarginM
  std::uint32_t probe_points = 0; ///< points of the adaptive end's probe pattern (0 = none)
  bool found_by_probe_pattern = false;  ///< ended by the adaptive end, not the fixed radius
  std::uint32_t line_resumptions = 0;   ///< signal lost while wide, primary line walked again (SearchConfig::lost_signal_steps)
  // Realistic receiver only:
  std::uint32_t primary_steps = 0;      ///< steps of the primary search before the first sample
  std::uint32_t measurements = 0;       ///< samples the filter took (steps without one: none heard)
  std::uint32_t wrong_attributions = 0; ///< pulses attributed to a signal not theirs
  std::uint32_t spurious_signals = 0;   ///< signal ids other than the transmitter's
};

struct Stats {
  double max = 0.0;
  double mean = 0.0;
  double median = 0.0;
};

struct EvaluationSummary {
  std::string filter = "sog";
  std::uint32_t trials = 0;
  std::uint64_t seed = 0;
  Stats error_m;
  Stats initial_distance_m;
  Stats steps;
  std::uint32_t not_found = 0;
  std::uint32_t errors_over_1m = 0;      ///< trials ending more than 1 m off (seed 000, Fig. 5's last bin)
  std::uint32_t false_found = 0;         ///< found farther than radius95 + kFalseFoundMarginM
  std::uint32_t found_by_probe_pattern = 0;  ///< trials ended by the adaptive end
  std::uint32_t resumed_line = 0;            ///< trials that walked the primary line again after losing the signal
  std::string receiver = "realistic";
  Stats primary_steps;                   ///< realistic: steps before the signal was first heard
  Stats measurements;                    ///< samples the filter took
  std::uint32_t wrong_attributions = 0;  ///< summed over trials
  std::uint32_t spurious_signals = 0;
  double ms_per_step_median = 0.0;
  double ms_per_step_p95 = 0.0;
  double nees_mean = 0.0;              ///< mean over trials of the per-trial converged-phase mean
  double nees_lower = 0.0;             ///< chi2_{3N}(0.025) / N
  double nees_upper = 0.0;             ///< chi2_{3N}(0.975) / N
  std::uint32_t nees_trials = 0;       ///< N: trials with a converged phase
  double nees_fraction_inside_95 = 0.0;  ///< samples inside [chi2_3(0.025), chi2_3(0.975)]
  double wall_s = 0.0;
  bool cancelled = false;
  std::vector<TrialResult> per_trial;
};

/// What one step of a trial saw and decided, for step-by-step traces (`sarloc-eval
/// --trace-trial`, `--trace-csv`). Valid only during the observer call; `sim` is at the pose
/// where `measurement` was taken, before the step is walked.
struct TrialStep {
  std::uint32_t trial = 0;
  std::uint32_t step = 0;
  const AvalancheSimulator& sim;
  const FieldMeasurement& measurement;
  const FilterStepResult& filter_result;
  const TransmitterFilter& filter;
  const Guidance& guidance;
  const VictimEstimate& estimate;
};
using StepObserver = std::function<void(const TrialStep&)>;

/// The filter setup.filter names, its random stream seeded with `seed` (particle filters).
std::unique_ptr<TransmitterFilter> make_transmitter_filter(const EvaluationSetup& setup, std::uint64_t seed);

/// One trial, deterministic for (setup, index). `observer`, if set, sees every step.
TrialResult run_trial(const EvaluationSetup& setup, std::uint32_t index,
                      const StepObserver& observer = {});

/// All trials in parallel; on_trial_done is called from worker threads (must be thread-safe).
/// `cancelled` is polled before each trial; when it returns true the remaining trials are
/// skipped and the summary covers the completed ones (summary.cancelled = true).
/// `observer` is called from worker threads too, steps of one trial in order.
EvaluationSummary run_evaluation(const EvaluationSetup& setup,
                                 const std::function<void()>& on_trial_done = {},
                                 const std::function<bool()>& cancelled = {},
                                 const StepObserver& observer = {});

Stats compute_stats(std::vector<double> values);


}  // namespace sarloc::avalanche
