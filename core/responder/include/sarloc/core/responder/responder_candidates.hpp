#pragma once
// The places a map-aided firefighter may be in while his position is ambiguous: "between N
// places", each with its weight (issue 65). Published beside the ResponderPosition.
#include <string>
#include <vector>

#include "sarloc/core/common/types.hpp"

namespace sarloc::responder {

struct PositionCandidate {
  GaussianPosition position;  ///< incident frame (ENU, m): the place's mean and spread
  std::int32_t floor = 0;
  double weight = 0.0;  ///< share of the belief, (0, 1]
};

struct ResponderCandidates {
  std::string responder_id;
  TimestampNs stamp = 0;                      ///< the ResponderPosition's
  std::vector<PositionCandidate> candidates;  ///< heaviest first; empty: no longer ambiguous
};

}  // namespace sarloc::responder
