#pragma once
// A rescuer's closed-loop search with the realistic receiver and the product's defaults, its
// estimator journaled: the journal a hand-over between sectors' daemons carries
// (estimator_journal.hpp). `each_epoch` may add calls of its own after an epoch's step.
#include <functional>

#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/estimator/estimator_journal.hpp"

namespace sarloc::test {

inline estimator::EstimatorJournal journaled_search(
    std::uint64_t seed, int epochs,
    const std::function<void(int epoch, estimator::JournaledEstimator&, TimestampNs now)>& each_epoch = {}) {
  const estimator::EstimatorConfigs configs;
  avalanche::AvalancheSimulator sim(avalanche::SimulationConfig{}, seed);
  estimator::JournaledEstimator journaled(
      estimator::make_estimator(estimator::ResponderRole::kAvalancheRescuer, "r1", configs), 1U << 20);
  TimestampNs now = 0;
  for (int epoch = 0; epoch < epochs; ++epoch) {
    std::optional<responder::Guidance> guidance;
    for (auto& sample : sim.listen()) {
      sample.rescuer_id = "r1";
      now = sample.stamp;
      const auto outcome = journaled.process(sample);
      if (const auto* out = std::get_if<estimator::EstimatorOutput>(&outcome); out != nullptr && out->guidance) {
        guidance = out->guidance;
      }
    }
    if (!guidance) guidance = journaled.coast(now);
    auto odometry = guidance ? sim.walk(guidance->bearing_rad, guidance->step_m) : sim.walk(0.0, 1.0);
    odometry.rescuer_id = "r1";
    now = odometry.interval_end;
    journaled.add_odometry(odometry);
    if (each_epoch) each_epoch(epoch, journaled, now);
  }
  return journaled.journal();
}

}  // namespace sarloc::test
