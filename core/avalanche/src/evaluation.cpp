#include "sarloc/core/avalanche/evaluation.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "sarloc/core/avalanche/grid_filter.hpp"
#include "sarloc/core/avalanche/particle_filter.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/parallel_trials.hpp"
#include "sarloc/core/common/position_nees.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::avalanche {

void EvaluationConfig::validate() const {
  require(trials != 0, "evaluation.trials", trials, "must be > 0");
  require(trials <= 1000000, "evaluation.trials", trials, "must be <= 1000000");
  require(threads <= 1024, "evaluation.threads", threads, "must be <= 1024");
  require(step_budget != 0, "evaluation.step_budget", step_budget, "must be > 0");
  require(step_budget <= 100000, "evaluation.step_budget", step_budget, "must be <= 100000");
}

void EvaluationSetup::validate() const {
  simulation.validate();
  sog.validate();
  particle.validate();
  grid.validate();
  search.validate();
  evaluation.validate();
}

Stats compute_stats(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  s.max = *std::max_element(v.begin(), v.end());
  s.mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  s.median = percentile(std::move(v), 0.5);
  return s;
}

namespace {
constexpr std::uint32_t kSwitchAfterSilentSteps = 5;
constexpr std::uint64_t kFilterStream = 0x66696c746572ULL;  // "filter"
}  // namespace

std::unique_ptr<TransmitterFilter> make_transmitter_filter(const EvaluationSetup& setup, std::uint64_t seed) {
  switch (setup.filter) {
    case FilterKind::kSog:
      return std::make_unique<SogFilter>(setup.sog, "sim", 1);
    case FilterKind::kPf:
    case FilterKind::kRbpf:
    case FilterKind::kRbpfImproved:
      return std::make_unique<ParticleFilter>(setup.filter, setup.sog, setup.particle, seed, "sim", 1);
    case FilterKind::kGrid:
      return std::make_unique<GridFilter>(setup.sog, setup.grid, "sim", 1);
  }
  throw ConfigError(std::string("filter = ") + to_string(setup.filter) + ": unknown");
}

TrialResult run_trial(const EvaluationSetup& setup, std::uint32_t index,
                      const StepObserver& observer) {
  using Clock = std::chrono::steady_clock;
  TrialResult tr;
  tr.index = index;
  AvalancheSimulator sim(setup.simulation, derive_seed(setup.evaluation.seed, index));
  const bool realistic = setup.simulation.receiver.kind == ReceiverKind::kRealistic;
  // The filter's own random stream: the scenario and the sensor noise stay those of trial i
  // whichever filter runs (derive_seed(seed, i) drives the simulator alone).
  const std::uint64_t filter_seed = derive_seed(derive_seed(setup.evaluation.seed, index), kFilterStream);
  std::unique_ptr<TransmitterFilter> owned = make_transmitter_filter(setup, filter_seed);
  TransmitterFilter* filter = owned.get();
  SearchController ctl(setup.search);
  tr.initial_distance_m = sim.true_horizontal_distance();
  // The first signal heard is searched. If it falls silent while another is heard more (the
  // separation split one transmitter in two at the edge of range), the search moves to that one.
  std::optional<std::uint32_t> signal;
  std::set<std::uint32_t> signals;
  std::map<std::uint32_t, std::uint32_t> heard;
  std::uint32_t silent = 0;
  for (std::uint32_t step = 1; step <= setup.evaluation.step_budget; ++step) {
    std::optional<FieldMeasurement> z, miss;  // miss: the signal's pulse was due and not heard
    if (realistic) {
      std::vector<FieldMeasurement> samples = sim.listen();
      for (auto& m : samples) {
        if (m.valid_axes == 0) {
          if (signal && m.signal_id == *signal) miss = m;
          continue;
        }
        signals.insert(m.signal_id);
        ++heard[m.signal_id];
        if (!signal) signal = m.signal_id;
        if (m.signal_id == *signal) z = m;
      }
      silent = z ? 0 : silent + 1;
      if (!z && silent >= kSwitchAfterSilentSteps) {
        for (auto& m : samples) {
          if (m.valid_axes == 0 || heard[m.signal_id] <= heard[*signal]) continue;
          signal = m.signal_id;
          z = m;
          miss.reset();
          owned = make_transmitter_filter(setup, derive_seed(filter_seed, m.signal_id));
          filter = owned.get();
          ctl = SearchController(setup.search);
          silent = 0;
          break;
        }
      }
    } else {
      z = sim.measure();
    }
    if (!z) {
      // Not heard: before the first sample the primary search walks its strip; after it, the
      // rescuer keeps heading for the estimate.
      if (!filter->initialised()) {
        ++tr.primary_steps;
        tr.initial_distance_m = sim.true_horizontal_distance();
        sim.walk(0.0, setup.search.step_length_m);
        continue;
      }
      tr.steps = step - tr.primary_steps;
      if (miss) filter->update(*miss);
      const Guidance g = ctl.coast(*filter);
      filter->add_odometry(sim.walk(g.bearing_rad, g.step_m));
      continue;
    }
    ++tr.measurements;
    const auto t0 = Clock::now();
    const FilterStepResult sr = filter->update(*z);
    if (sr.reinitialised) ++tr.reinitialisations;
    const auto t1 = Clock::now();
    tr.step_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    const Guidance g = ctl.guide(*filter, *z);
    const VictimEstimate e = filter->estimate(0);
    const Vec3 err = e.relative.position - sim.true_relative_position();
    const double nees = position_nees(err, e.relative.covariance);
    tr.final_nees = nees;
    if (e.status == EstimatorStatus::kConverged) {
      tr.nees.push_back(nees);
      if (tr.first_converged_step == 0) tr.first_converged_step = step - tr.primary_steps;
    }
    if (g.mode == GuidanceMode::kOpening) ++tr.flux_line_steps;
    tr.steps = step - tr.primary_steps;
    tr.error_m = err.norm();
    tr.horizontal_error_m = err.head<2>().norm();
    tr.final_components = static_cast<std::uint32_t>(filter->size());
    tr.radius95_m = radius95_3d(e.relative.covariance);
    tr.probe_points = static_cast<std::uint32_t>(ctl.probe_pattern().size());
    if (observer) observer(TrialStep{index, step, sim, *z, sr, *filter, g, e});
    if (g.mode == GuidanceMode::kFound) {
      tr.found = true;
      tr.found_by_probe_pattern = ctl.found_by_probe_pattern();
      tr.false_found = tr.error_m > tr.radius95_m + kFalseFoundMarginM;
      break;
    }
    filter->add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  tr.line_resumptions = ctl.line_resumptions();
  tr.wrong_attributions = sim.wrong_attributions();
  tr.spurious_signals = signals.empty() ? 0 : static_cast<std::uint32_t>(signals.size() - 1);
  return tr;
}

EvaluationSummary run_evaluation(const EvaluationSetup& setup,
                                 const std::function<void()>& on_trial_done,
                                 const std::function<bool()>& cancelled,
                                 const StepObserver& observer) {
  setup.validate();
  const auto start = std::chrono::steady_clock::now();
  TrialRun<TrialResult> run = run_parallel_trials<TrialResult>(
      setup.evaluation.trials, setup.evaluation.threads,
      [&](std::uint32_t i) { return run_trial(setup, i, observer); }, on_trial_done, cancelled);
  std::vector<TrialResult> results = std::move(run.results);

  EvaluationSummary s;
  s.filter = to_string(setup.filter);
  s.cancelled = run.cancelled;
  s.trials = static_cast<std::uint32_t>(results.size());
  s.seed = setup.evaluation.seed;
  s.receiver = to_string(setup.simulation.receiver.kind);
  std::vector<double> err, dist, steps, ms, trial_nees, primary, measurements;
  std::size_t inside = 0, samples = 0;
  const double lo3 = chi_square_quantile(0.025, 3.0), hi3 = chi_square_quantile(0.975, 3.0);
  for (const auto& r : results) {
    err.push_back(r.error_m);
    dist.push_back(r.initial_distance_m);
    steps.push_back(r.steps);
    primary.push_back(r.primary_steps);
    measurements.push_back(r.measurements);
    s.wrong_attributions += r.wrong_attributions;
    s.spurious_signals += r.spurious_signals;
    if (!r.found) ++s.not_found;
    if (r.error_m > 1.0) ++s.errors_over_1m;
    if (r.false_found) ++s.false_found;
    if (r.found_by_probe_pattern) ++s.found_by_probe_pattern;
    if (r.line_resumptions > 0) ++s.resumed_line;
    ms.insert(ms.end(), r.step_ms.begin(), r.step_ms.end());
    if (!r.nees.empty()) {
      trial_nees.push_back(std::accumulate(r.nees.begin(), r.nees.end(), 0.0) /
                           static_cast<double>(r.nees.size()));
      for (double v : r.nees) {
        ++samples;
        if (v >= lo3 && v <= hi3) ++inside;
      }
    }
  }
  s.error_m = compute_stats(err);
  s.initial_distance_m = compute_stats(dist);
  s.steps = compute_stats(steps);
  s.primary_steps = compute_stats(primary);
  s.measurements = compute_stats(measurements);
  s.ms_per_step_median = percentile(ms, 0.5);
  s.ms_per_step_p95 = percentile(ms, 0.95);
  s.nees_trials = static_cast<std::uint32_t>(trial_nees.size());
  if (!trial_nees.empty()) {
    const double nt = static_cast<double>(trial_nees.size());
    s.nees_mean = std::accumulate(trial_nees.begin(), trial_nees.end(), 0.0) / nt;
    s.nees_lower = chi_square_quantile(0.025, 3.0 * nt) / nt;
    s.nees_upper = chi_square_quantile(0.975, 3.0 * nt) / nt;
    s.nees_fraction_inside_95 = static_cast<double>(inside) / static_cast<double>(samples);
  }
  s.per_trial = std::move(results);
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

}  // namespace sarloc::avalanche
