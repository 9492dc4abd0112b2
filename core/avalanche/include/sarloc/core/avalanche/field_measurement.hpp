#pragma once
// One 3-axis avalanche-beacon field sample, for one separated signal (one transmitter).
#include <cstdint>
#include <optional>
#include <string>

#include "sarloc/core/common/types.hpp"
#include "sarloc/core/responder/signal_event.hpp"
#include "sarloc/core/responder/transmitter_signature.hpp"

namespace sarloc::avalanche {

/// Receiver orientation in the geographic frame G (roll, pitch, yaw in rad, seed 000 eq. (2))
/// from an attitude sensor, with its 3x3 covariance (rad^2).
struct OrientationObservation {
  Vec3 rpy = Vec3::Zero();
  Mat3 covariance = Mat3::Identity();
};

/// What the receiver's signal separation says about a signal in this sample
/// (signal_separator.hpp): the event is carried by the first sample after it.
using responder::SignalEvent;

struct FieldMeasurement {
  std::string rescuer_id;
  std::uint32_t signal_id = 0;       ///< transmitter as separated by the receiver
  std::uint64_t sequence = 0;        ///< per (rescuer, signal), strictly increasing
  TimestampNs stamp = 0;
  /// Magnetic field in the receiver antenna frame R (A/m), up to its sign: a real receiver
  /// does not carry the carrier's phase from pulse to pulse, so every filter reads it as +-field.
  Vec3 field = Vec3::Zero();
  Vec3 noise_stddev = Vec3::Zero();  ///< per-axis 1-sigma noise (A/m)
  /// Bit i set: axis i carries signal. A clear bit: the axis was below the receiver's
  /// detection threshold (its value is near zero and its sign unknown); field[i] is ignored.
  std::uint8_t valid_axes = 0b111;
  SignalEvent event = SignalEvent::kNone;
  /// Pulses of the receiver's last listening window it could not attribute to any signal.
  std::uint32_t unattributed_pulses = 0;
  /// The signal's transmitter as the receiver's separation has measured it so far (unknown from
  /// an ideal receiver).
  responder::TransmitterSignature transmitter;
  std::optional<OrientationObservation> orientation;
};

}  // namespace sarloc::avalanche
