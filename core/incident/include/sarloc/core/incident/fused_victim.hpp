#pragma once
// A victim as incident command sees it: all rescuers' estimates of one transmitter fused.
#include <string>
#include <vector>

#include "sarloc/core/common/types.hpp"
#include "sarloc/core/responder/signal_event.hpp"

namespace sarloc::incident {

enum class VictimState : std::uint8_t { kUnconfirmed = 0, kLocated = 1, kFound = 2, kRecovered = 3 };

struct VictimSource {
  std::string rescuer_id;
  std::uint32_t signal_id = 0;
  TimestampNs last_update = 0;
  /// The rescuer's signal separation's last event on this signal (lost and reacquired,
  /// separated after a merge): the commander sees which contributions went through one.
  responder::SignalEvent signal_event = responder::SignalEvent::kNone;
  TimestampNs signal_event_stamp = 0;
};

struct FusedVictim {
  std::uint32_t victim_id = 0;          ///< stable for the whole incident
  GaussianPosition position;      ///< incident frame (ENU, m)
  std::int32_t floor = 0;               ///< building floor (0 = ground or outdoors)
  std::vector<VictimSource> sources;
  VictimState state = VictimState::kUnconfirmed;
  TimestampNs first_seen = 0;
  TimestampNs last_update = 0;
  TimestampNs located_at = 0;           ///< 0 while not located
  TimestampNs found_at = 0;             ///< 0 while not found
  /// Two estimators of one of its sources disagree (VictimFusion): the picture cannot tell
  /// which is right, so that source confirms nothing and the dashboard shows the flag.
  bool evidence_conflict = false;
  /// A reporter cannot tell one of its sources here from another of its signals, bound to this
  /// victim id (VictimFusion, "Repeats"): possibly one transmitter seen twice. 0: none.
  std::uint32_t possibly_same_as = 0;
};

inline const char* to_string(VictimState s) {
  switch (s) {
    case VictimState::kUnconfirmed: return "unconfirmed";
    case VictimState::kLocated: return "LOCATED";
    case VictimState::kFound: return "FOUND";
    case VictimState::kRecovered: return "recovered";
  }
  return "unconfirmed";
}

/// Found by a rescuer (and possibly recovered since).
inline bool is_found(VictimState s) { return s == VictimState::kFound || s == VictimState::kRecovered; }

}  // namespace sarloc::incident
