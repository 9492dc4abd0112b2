#pragma once
// Accountability of responders, grouped by team (personnel accountability report, PAR).
#include <string>
#include <vector>

#include "sarloc/core/common/types.hpp"
#include "sarloc/core/responder/responder_position.hpp"

namespace sarloc::incident {

/// kSignedOff: the responder's device stopped in order and said so (it disposed its own
/// position instance): accounted for, no alarm. A killed device is kLost. On the wire
/// (MemberStatus) it is LINK_LOST with RESPONDER_FLAG_SIGNED_OFF: no new enumerator.
enum class LinkState : std::uint8_t { kAlive = 0, kStale = 1, kLost = 2, kSignedOff = 3 };
/// "alive", "stale", "lost", "signed_off" (the picture's JSON and the mission summary).
const char* to_string(LinkState link);
/// What a person reads: "alive", "stale", "LOST", "signed off" (the post-mission report).
const char* display_name(LinkState link);

enum class AccountabilityState : std::uint8_t { kAccounted = 0, kPending = 1, kMissing = 2 };

struct MemberStatus {
  std::string responder_id;
  GaussianPosition last_position;  ///< incident frame
  TimestampNs last_seen = 0;
  LinkState link = LinkState::kAlive;
  AccountabilityState accountability = AccountabilityState::kPending;
  TimestampNs position_stamp = 0;  ///< device stamp of last_position (0 while none)
  bool has_position = false;       ///< false: only liveliness heard so far, no position yet
  std::int32_t floor = 0;          ///< of last_position (building floor, 0 = ground or outdoors)
  responder::PositionSource source = responder::PositionSource::kGnss;  ///< of last_position
  bool converged = false, map_error_suspected = false, confirmed = false;  ///< of last_position (map-aided)
  bool ambiguous = false;  ///< of last_position: map-aided, between 2-4 places (ResponderCandidates)
};

struct TeamStatus {
  std::string team_id;
  std::vector<MemberStatus> members;
  TimestampNs stamp = 0;
};

}  // namespace sarloc::incident
