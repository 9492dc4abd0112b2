#pragma once
// What incident fusion takes in: one reporter's estimate of one victim, already in the
// incident frame. Generic over the detector: an avalanche rescuer's beacon filter today; a
// robot's camera or a dog team (seed 002, section 5) can report the same way later.
//
//   SourceEstimate s = make_source_estimate(victim_estimate, fix_at(victim_estimate.stamp));
//   fusion.update(s);
#include <cstdint>
#include <string>

#include "sarloc/core/common/types.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/core/responder/victim_estimate.hpp"

namespace sarloc::incident {

/// How far the reporter's own estimate has come.
enum class SourceState : std::uint8_t {
  kTentative = 0,  ///< several hypotheses: the mean means nothing, not fused
  kConverged = 1,  ///< one mode
  kLocated = 2,    ///< precise enough to walk onto
  kFound = 3,      ///< the reporter stands over it
};

struct SourceEstimate {
  std::string rescuer_id;      ///< who reported it (a rescuer, a robot, a dog handler)
  std::uint32_t signal_id = 0; ///< the reporter's id of this victim (e.g. a beacon signal)
  TimestampNs stamp = 0;
  GaussianPosition position;   ///< incident ENU (m, m^2)
  std::int32_t floor = 0;      ///< building floor (0 = ground or outdoors)
  /// Heights are above the snow surface and the victim is buried (an avalanche beacon placed
  /// with a GNSS fix): an estimate confidently above z = 0 is a mirror solution, refused.
  bool below_surface = false;
  SourceState state = SourceState::kTentative;
  /// Which estimator computed it (e.g. the DDS writer): a rescuer's device and the core daemon
  /// both estimate the same (rescuer, signal) from the same samples, so they must agree.
  std::string estimator;
  /// Computed on the reporter's own device, which saw every sample (nothing crosses a network
  /// between its sensors and its estimator); the core daemon's copy can miss samples.
  bool from_device = false;
  /// When incident command heard it (mission time; 0: at its stamp). A source is active while
  /// heard within source_timeout_s: after a radio fade a device's FOUND arrives long after its
  /// stamp (it is republished with the stamp of the epoch it was found in) and still counts.
  TimestampNs received = 0;
  /// The reporter's signal separation's last event on this signal (VictimEstimate).
  responder::SignalEvent signal_event = responder::SignalEvent::kNone;
  TimestampNs signal_event_stamp = 0;
  /// The reporter's word that this signal is (kConfirmed) or may be (kSuspected) its signal
  /// repeat_of_signal again: one transmitter split in two (VictimEstimate::repeat).
  responder::RepeatState repeat = responder::RepeatState::kNone;
  std::uint32_t repeat_of_signal = 0;
  /// The transmitter as the reporter's receiver measured it (VictimEstimate::transmitter).
  responder::TransmitterSignature transmitter;
};

/// Where the reporter's detector was at the estimate's stamp (ResponderTrack::at).
struct ReporterFix {
  GaussianPosition antenna;     ///< incident frame (m, m^2)
  std::int32_t floor = 0;
  bool heights_above_surface = false;  ///< outdoors on snow: z is the height above the surface
};

/// A responder's position as the fix that places the victims it reports. A GNSS position
/// (outdoors) keeps its horizontal part, and its height becomes the antenna's height above the
/// snow surface (what diggers need; GNSS altitude is poor and says nothing about a burial
/// depth). Every other source (map-aided indoors, dead reckoning, manual) keeps its height
/// and floor as reported.
ReporterFix reporter_fix_of(const responder::ResponderPosition& position, double antenna_height_m,
                            double antenna_height_sigma_m);

SourceState source_state_of(responder::EstimatorStatus status);

/// Relative estimate + the reporter's fix at its stamp -> SourceEstimate through
/// to_incident_frame (incident_transform.hpp). A victim placed from heights above the snow is
/// below_surface.
SourceEstimate make_source_estimate(const responder::VictimEstimate& estimate, const ReporterFix& fix);

}  // namespace sarloc::incident
