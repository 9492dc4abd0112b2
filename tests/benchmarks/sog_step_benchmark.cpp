// One SogFilter::process() step (odometry + field update + prune + merge) at 1700, 400 and 50
// components. The filter is initialised from a simulated first measurement with
// sog.initial_components = N and stepped once per iteration on a copy, so every iteration
// sees exactly N components (the timing of the eval tool's first step). The second argument 0
// times the filter without what the receiver's physics added on 2026-12-05 (the field at the
// carrier, the calibration as consider parameters): the cost of each shipped step's model.
// BM_LookaheadHeading: one information-aware opening decision on that first mixture.
// BM_ResumeJournal: what a daemon taking a rescuer over from another's sector spends
// (estimator::resume_estimator): the journal of a closed-loop search with the realistic receiver
// after `steps` epochs, replayed into a new estimator; counters give its entries and bytes.
#include <benchmark/benchmark.h>

#include "sarloc/core/avalanche/lookahead_heading.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "support/journaled_search.hpp"

namespace {

using namespace sarloc::avalanche;

void BM_SogStep(benchmark::State& state) {
  SogConfig cfg;
  cfg.initial_components = static_cast<std::uint32_t>(state.range(0));
  if (state.range(1) == 0) {
    cfg.field_carrier_hz = 0.0;
    cfg.calibration_gain_sigma = 0.0;
    cfg.calibration_pointing_sigma_deg = 0.0;
  }
  AvalancheSimulator sim(SimulationConfig{}, sarloc::derive_seed(7, 0));
  SogFilter base(cfg, "sim", 1);
  base.process(sim.measure());
  const Odometry odo = sim.walk(0.3, 1.0);
  const FieldMeasurement z = sim.measure();
  std::size_t n = 0;
  for (auto _ : state) {
    state.PauseTiming();
    SogFilter f = base;
    state.ResumeTiming();
    f.add_odometry(odo);
    benchmark::DoNotOptimize(f.process(z));
    n = base.size();
  }
  state.counters["components"] = static_cast<double>(n);
}

void BM_LookaheadHeading(benchmark::State& state) {
  SogConfig cfg;
  AvalancheSimulator sim(SimulationConfig{}, sarloc::derive_seed(7, 0));
  SogFilter f(cfg, "sim", 1);
  f.process(sim.measure());
  f.add_odometry(sim.walk(0.3, 1.0));
  f.process(sim.measure());
  const LookaheadConfig look;
  for (auto _ : state)
    benchmark::DoNotOptimize(
        lookahead_heading(f.hypotheses(), look, 1.0, cfg.noise(), cfg.noise_floor_A_per_m));
  state.counters["components"] = static_cast<double>(f.size());
}

void BM_ResumeJournal(benchmark::State& state) {
  const auto journal = sarloc::test::journaled_search(sarloc::derive_seed(7, 0), static_cast<int>(state.range(0)));
  const sarloc::estimator::EstimatorConfigs configs;
  for (auto _ : state) benchmark::DoNotOptimize(sarloc::estimator::resume_estimator(journal, configs, 1U << 20));
  state.counters["entries"] = static_cast<double>(journal.entries.size());
  state.counters["bytes"] = static_cast<double>(journal.entries.size() * sizeof(sarloc::estimator::JournalEntry));
}

}  // namespace

BENCHMARK(BM_SogStep)
    ->ArgsProduct({{1700, 400, 50}, {1, 0}})
    ->ArgNames({"components", "shipped_model"})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LookaheadHeading)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ResumeJournal)->Arg(20)->Arg(60)->Arg(300)->ArgName("epochs")->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
