#pragma once
// What the rescuer should do next for one signal (seed 000, section III-C).
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::responder {

enum class GuidanceMode : std::uint8_t {
  kOpening = 0,     ///< opening (coarse) search: posterior bearing or flux line (SearchConfig)
  kApproach = 1,    ///< walk toward the mixture mean
  kFineSearch = 2,  ///< close in: small steps onto the mean
  kFound = 3,       ///< stop and probe
  /// No signal to follow: walk the search plan's strip (incident::strip_guidance). The
  /// device's own guidance, never on the Guidance topic (its IDL enum stops at FOUND).
  kPrimarySearch = 4,
};

struct Guidance {
  std::string rescuer_id;
  std::uint32_t signal_id = 0;
  TimestampNs stamp = 0;
  GuidanceMode mode = GuidanceMode::kOpening;
  /// Direction to walk relative to the receiver's forward axis (rad, counter-clockwise
  /// positive, i.e. towards the left): what the device's arrow shows.
  double bearing_rad = 0.0;
  /// The same direction in G (ENU): 0 = east, pi/2 = north. Only as good as the yaw estimate.
  double heading_rad = 0.0;
  double distance_m = 0.0;       ///< horizontal distance to the estimate (m)
  double uncertainty_radius_m = 0.0;  ///< 95 % horizontal radius of the estimate (m)
  /// Length of the next step (m): the nominal step, shorter in fine search, 0 when found.
  double step_m = 0.0;
};

}  // namespace sarloc::responder
