// One update of the particle-filter baselines (docs/estimation/baselines.md): odometry, the
// attitude reading and a field sample for every particle, then resampling when N_eff is low.
// The filter is initialised from a simulated first measurement, walked 10 steps, and each
// iteration updates a copy, so every iteration sees the same cloud. Arg: the particle count.
#include <benchmark/benchmark.h>

#include "sarloc/core/avalanche/particle_filter.hpp"
#include "sarloc/core/avalanche/simulator.hpp"

namespace {

using namespace sarloc::avalanche;

void particle_step(benchmark::State& state, FilterKind kind) {
  ParticleFilterConfig cfg;
  cfg.particles = cfg.improved_particles = static_cast<std::uint32_t>(state.range(0));
  SimulationConfig sim_cfg;
  sim_cfg.receiver.kind = ReceiverKind::kIdeal;  // a sample every step
  AvalancheSimulator sim(sim_cfg, sarloc::derive_seed(7, 0));
  ParticleFilter base(kind, SogConfig{}, cfg, 11, "sim", 1);
  base.update(sim.measure());
  for (int k = 0; k < 10; ++k) {
    base.add_odometry(sim.walk(0.3, 1.0));
    base.update(sim.measure());
  }
  const Odometry odo = sim.walk(0.3, 1.0);
  const FieldMeasurement z = sim.measure();
  for (auto _ : state) {
    state.PauseTiming();
    ParticleFilter f = base;
    state.ResumeTiming();
    f.add_odometry(odo);
    benchmark::DoNotOptimize(f.update(z));
  }
  state.counters["particles"] = static_cast<double>(base.size());
}

void BM_RbpfStep(benchmark::State& state) { particle_step(state, FilterKind::kRbpf); }
void BM_RbpfImprovedStep(benchmark::State& state) { particle_step(state, FilterKind::kRbpfImproved); }
void BM_VanillaPfStep(benchmark::State& state) { particle_step(state, FilterKind::kPf); }

}  // namespace

BENCHMARK(BM_RbpfStep)->Arg(5000)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RbpfImprovedStep)->Arg(5000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VanillaPfStep)->Arg(5000)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
