// What the core daemon's firefighters cost (issue 14: 20 firefighters on the 1040 m2 floor must
// keep it real-time on one core). Twenty simulated searches of warehouse-1040 (both hands, each
// from the entry its walk used), their boot odometry made up front by FirefighterDevice on
// simulated MTi-3 samples; one iteration runs the twenty FirefighterEstimators over all of it on
// one thread, step by step in time order as a daemon's worker would. Counters:
//   real_time_factor  mission seconds per processing second (>= 1: keeps up on one core)
//   ms_per_step_p50 / _p99 / _max  one firefighter's step (predict, and the pattern comparison when due)
// Run: build/bin/sarloc-bench-firefighters (docs/benchmarks.md has the figures).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <random>

#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/core/common/statistics.hpp"
#include "sarloc/core/estimator/firefighter_device.hpp"
#include "sarloc/core/estimator/make_estimator.hpp"
#include "sarloc/core/firefighter/foot_trajectory.hpp"
#include "sarloc/core/firefighter/imu_error_model.hpp"
#include "sarloc/core/firefighter/search_walk.hpp"

namespace {

using namespace sarloc;

constexpr int kFirefighters = 20;
constexpr double kSearchS = 120.0;

struct Crew {
  estimator::EstimatorConfigs configs;
  std::vector<std::vector<responder::Odometry>> odometry;  // per firefighter, in time order
};

Crew make_crew() {
  Crew crew;
  auto& f = crew.configs.firefighter;
  f.building = std::make_shared<const firefighter::BuildingModel>(
      app::load_floor_plan(std::string(SARLOC_SOURCE_DIR) + "/config/buildings/warehouse-1040.yaml"),
      firefighter::BuildingModelConfig{});
  for (int i = 0; i < kFirefighters; ++i) {
    const std::string id = "ff" + std::to_string(i + 1);
    std::mt19937_64 rng(1000 + static_cast<std::uint64_t>(i));
    firefighter::SearchWalkConfig walk;
    walk.duration_s = kSearchS;
    const auto hand = i % 2 == 0 ? firefighter::Hand::kRight : firefighter::Hand::kLeft;
    const auto search = firefighter::generate_search_walk(f.building->plan(), walk, hand, rng);
    f.entry_of[id] = {search.entry, hand};
    const firefighter::FootTrajectory foot(search.leader);
    firefighter::ImuErrors errors(firefighter::ImuErrorConfig{}, rng);
    estimator::FirefighterDevice device(id, "crew", estimator::FirefighterDeviceConfig{}, 0);
    std::vector<responder::Odometry> steps;
    for (const auto& ideal : foot.imu_samples(100.0)) {
      device.push(errors.apply(ideal, rng));
      if (auto o = device.take_odometry()) steps.push_back(*o);
    }
    crew.odometry.push_back(std::move(steps));
  }
  crew.configs.validate();
  return crew;
}

void BM_TwentyFirefightersOnTheWarehouse(benchmark::State& state) {
  const Crew crew = make_crew();
  std::vector<double> step_ms;
  double mission_s = 0.0, processing_s = 0.0;
  for (auto _ : state) {
    std::vector<std::unique_ptr<estimator::ResponderEstimator>> estimators;
    for (int i = 0; i < kFirefighters; ++i) {
      estimators.push_back(estimator::make_estimator(estimator::ResponderRole::kFirefighter,
                                                     "ff" + std::to_string(i + 1), crew.configs));
    }
    std::size_t steps = 0;
    for (const auto& o : crew.odometry) steps = std::max(steps, o.size());
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t k = 0; k < steps; ++k) {
      for (int i = 0; i < kFirefighters; ++i) {
        if (k >= crew.odometry[i].size()) continue;
        const auto s0 = std::chrono::steady_clock::now();
        benchmark::DoNotOptimize(estimators[i]->add_odometry(crew.odometry[i][k]));
        step_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s0).count());
      }
    }
    processing_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    mission_s += 1e-9 * static_cast<double>(crew.odometry[0].back().interval_end - crew.odometry[0].front().interval_start);
  }
  state.counters["real_time_factor"] = mission_s / processing_s;
  state.counters["ms_per_step_p50"] = percentile(step_ms, 0.5);
  state.counters["ms_per_step_p99"] = percentile(step_ms, 0.99);
  state.counters["ms_per_step_max"] = *std::max_element(step_ms.begin(), step_ms.end());
}

BENCHMARK(BM_TwentyFirefightersOnTheWarehouse)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);

}  // namespace

BENCHMARK_MAIN();
