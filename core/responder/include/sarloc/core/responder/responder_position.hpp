#pragma once
// Where a responder (firefighter, avalanche rescuer) is, in the incident frame.
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::responder {

enum class PositionSource : std::uint8_t { kGnss = 0, kMapAided = 1, kDeadReckoning = 2, kManual = 3 };

struct ResponderPosition {
  std::string responder_id;
  std::string team_id;
  TimestampNs stamp = 0;
  GaussianPosition position;  ///< incident frame (ENU, m)
  double heading_rad = 0.0;         ///< ENU yaw of the body x axis
  std::int32_t floor = 0;           ///< building floor (0 = ground / outdoors)
  PositionSource source = PositionSource::kGnss;
  bool converged = false;
  bool map_error_suspected = false;
  /// Map-aided only: converged for a while, no map error since the start, and traced back to an
  /// entry (firefighter::MapEstimate::confirmed): a position incident command may act on.
  bool confirmed = false;
  /// Map-aided only, never with `converged`: the estimate is in 2-4 compact places
  /// (firefighter::MapEstimate::ambiguous); ResponderCandidates names them.
  bool ambiguous = false;
};

}  // namespace sarloc::responder
