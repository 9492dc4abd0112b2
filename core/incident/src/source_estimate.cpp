#include "sarloc/core/incident/source_estimate.hpp"

#include "sarloc/core/incident/incident_transform.hpp"

namespace sarloc::incident {

ReporterFix reporter_fix_of(const responder::ResponderPosition& position, double antenna_height_m,
                            double antenna_height_sigma_m) {
  ReporterFix fix;
  fix.antenna = position.position;
  fix.floor = position.floor;
  if (position.source == responder::PositionSource::kGnss) {
    fix.antenna.position.z() = antenna_height_m;
    fix.antenna.covariance.row(2).setZero();
    fix.antenna.covariance.col(2).setZero();
    fix.antenna.covariance(2, 2) = antenna_height_sigma_m * antenna_height_sigma_m;
    fix.heights_above_surface = true;
  }
  return fix;
}

SourceState source_state_of(responder::EstimatorStatus status) {
  using responder::EstimatorStatus;
  switch (status) {
    case EstimatorStatus::kInitialising:
    case EstimatorStatus::kMultimodal: return SourceState::kTentative;
    case EstimatorStatus::kConverged: return SourceState::kConverged;
    case EstimatorStatus::kLocated: return SourceState::kLocated;
    case EstimatorStatus::kFound: return SourceState::kFound;
  }
  return SourceState::kTentative;
}

SourceEstimate make_source_estimate(const responder::VictimEstimate& estimate, const ReporterFix& fix) {
  SourceEstimate s;
  s.rescuer_id = estimate.rescuer_id;
  s.signal_id = estimate.signal_id;
  s.stamp = estimate.stamp;
  s.signal_event = estimate.signal_event;
  s.signal_event_stamp = estimate.signal_event_stamp;
  s.repeat = estimate.repeat;
  s.repeat_of_signal = estimate.repeat_of_signal;
  s.transmitter = estimate.transmitter;
  s.state = source_state_of(estimate.status);
  s.position = to_incident_frame(estimate.relative, fix.antenna);
  s.floor = fix.floor;
  s.below_surface = fix.heights_above_surface;
  return s;
}

}  // namespace sarloc::incident
