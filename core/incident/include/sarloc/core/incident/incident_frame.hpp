#pragma once
// The incident's ENU frame as incident command publishes it (IncidentFrame topic): its WGS-84
// origin, and when it was established (the first instance to take over stamps it; later ones
// adopt it, so every position of the incident keeps one origin and one start).
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::incident {

struct IncidentFrame {
  std::string incident_id;
  GeodeticOrigin origin;
  std::string name;
  TimestampNs established = 0;  ///< mission time; 0 until an instance takes over
};

}  // namespace sarloc::incident
