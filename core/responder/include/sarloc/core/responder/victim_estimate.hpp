#pragma once
// A detector's estimate of one victim, relative to the responder who carries the detector: the
// avalanche filter's reduced mixture today; a robot's camera or a dog team's handler later.
// Incident command places it in the incident frame with the responder's position at `stamp`
// (incident/source_estimate.hpp).
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/common/types.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/core/responder/signal_event.hpp"
#include "sarloc/core/responder/transmitter_signature.hpp"

namespace sarloc::responder {

enum class EstimatorStatus : std::uint8_t {
  kInitialising = 0,  ///< no measurement yet
  kMultimodal = 1,    ///< several hypotheses alive
  kConverged = 2,     ///< one dominant mode
  kLocated = 3,       ///< uncertainty small enough to walk onto it (docs/estimation/avalanche.md)
  kFound = 4,         ///< rescuer stands over the estimate: probe here
};

/// Whether this signal is another signal of the same detector again: one transmitter split into
/// two signals by the separation (avalanche/same_transmitter.hpp).
enum class RepeatState : std::uint8_t {
  kNone = 0,       ///< a transmitter of its own, as far as the detector can tell
  kSuspected = 1,  ///< cannot yet be told apart from repeat_of_signal: confirms nothing
  kConfirmed = 2,  ///< stood over: the same transmitter as repeat_of_signal, found there
};
/// "none", "suspected", "confirmed".
const char* to_string(RepeatState state);

struct MixtureComponentSummary {
  double weight = 0.0;
  Vec3 mean = Vec3::Zero();            ///< rescuer-relative frame G_k (m)
  Mat3 covariance = Mat3::Identity();  ///< m^2
};

struct VictimEstimate {
  std::string rescuer_id;
  std::uint32_t signal_id = 0;         ///< the detector's id of this victim (a beacon signal)
  TimestampNs stamp = 0;
  EstimatorStatus status = EstimatorStatus::kInitialising;
  GaussianPosition relative;           ///< victim in G_k (rescuer-centred, ENU-aligned)
  std::vector<MixtureComponentSummary> top_components;  ///< highest weights first
  std::uint32_t live_components = 0;
  Vec3 moment = Vec3::Zero();          ///< beacon moment in G (A m^2); zero without a beacon
  /// The last change the detector's signal separation reported on this signal (new, reacquired
  /// after loss, separated after a merge) and the stamp of the sample that carried it.
  SignalEvent signal_event = SignalEvent::kNone;
  TimestampNs signal_event_stamp = 0;
  /// kSuspected / kConfirmed: possibly / surely the transmitter of repeat_of_signal (a signal
  /// of the same detector that is found or located), so this estimate confirms no victim.
  RepeatState repeat = RepeatState::kNone;
  std::uint32_t repeat_of_signal = 0;  ///< 0 with kNone
  /// The transmitter this signal follows, as the detector's receiver measured it (unknown from
  /// an ideal receiver, or before its separation knows it).
  TransmitterSignature transmitter;
  /// Where the responder was at `stamp`, when the estimate's writer knows it (the device's own
  /// estimates carry it): placed with this, the estimate needs no responder_position of its
  /// epoch, which a long radio fade can lose for good.
  std::optional<ResponderPosition> reporter;
};

}  // namespace sarloc::responder
