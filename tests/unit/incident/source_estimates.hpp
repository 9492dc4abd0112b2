#pragma once
// Victim-fusion tests' inputs: one rescuer's signal, estimated at a stamp and a position.
#include "sarloc/core/incident/victim_fusion.hpp"

namespace sarloc::incident::test {

constexpr TimestampNs kSec = 1'000'000'000;

/// A converged avalanche estimate of `rescuer`'s `signal` at `p` (sigma per axis), from the
/// reporter's own device unless the test says otherwise.

inline SourceEstimate src(const std::string& rescuer, std::uint32_t signal, TimestampNs t, const Vec3& p,
                   double sigma = 1.5, responder::EstimatorStatus st = responder::EstimatorStatus::kConverged) {
  SourceEstimate s;
  s.rescuer_id = rescuer;
  s.signal_id = signal;
  s.stamp = t;
  s.position.position = p;
  s.position.covariance = sigma * sigma * Mat3::Identity();
  s.state = source_state_of(st);
  s.below_surface = true;  // avalanche victims: heights above the snow
  s.from_device = true;     // the reporter's own estimate unless a test says otherwise
  return s;
}

}  // namespace sarloc::incident::test
