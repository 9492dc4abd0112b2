#pragma once
// Every kind of sensor sample a responder's device sends besides odometry: one alternative per
// sensor. The daemon's machinery handles a SensorSample without looking inside (its responder,
// stamp and sequence are all it needs); each estimator takes the alternatives of its role and
// refuses the others (RejectReason::kWrongRole).
#include <string>
#include <variant>

#include "sarloc/core/avalanche/field_measurement.hpp"

namespace sarloc::estimator {

using SensorSample = std::variant<avalanche::FieldMeasurement>;

const std::string& responder_of(const SensorSample& sample);
TimestampNs stamp_of(const SensorSample& sample);
/// Strictly increasing per (responder, channel) on the wire.
std::uint64_t sequence_of(const SensorSample& sample);
/// The channel its sequence counts in (a beacon signal), per responder.
std::uint32_t signal_of(const SensorSample& sample);

}  // namespace sarloc::estimator
