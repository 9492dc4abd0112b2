#include "sarloc/core/estimator/avalanche_rescuer_estimator.hpp"

namespace sarloc::estimator {

AvalancheRescuerEstimator::AvalancheRescuerEstimator(std::string rescuer_id, avalanche::RescuerSearchConfig config)
    : search_(std::move(rescuer_id), std::move(config)) {}

Outcome AvalancheRescuerEstimator::add_odometry(const responder::Odometry& odometry) {
  if (auto rejected = search_.add_odometry(odometry)) return *rejected;
  return EstimatorOutput{};
}

bool AvalancheRescuerEstimator::add_unknown_motion(TimestampNs from, TimestampNs until) {
  return search_.add_unknown_motion(from, until);
}

Outcome AvalancheRescuerEstimator::process(const SensorSample& sample) {
  const auto* field = std::get_if<avalanche::FieldMeasurement>(&sample);
  if (field == nullptr) {
    return responder::reject(responder::RejectReason::kWrongRole, search_.rescuer_id(),
                             "an avalanche rescuer takes field measurements only");
  }
  auto outcome = search_.process(*field);
  if (auto* rejected = std::get_if<responder::Rejection>(&outcome)) return std::move(*rejected);
  auto& update = std::get<avalanche::SearchUpdate>(outcome);
  EstimatorOutput out;
  if (update.estimate) out.estimates.push_back(std::move(*update.estimate));
  out.guidance = std::move(update.guidance);
  return out;
}

std::optional<responder::Guidance> AvalancheRescuerEstimator::coast(TimestampNs stamp) {
  return search_.coast(stamp);
}

}  // namespace sarloc::estimator
