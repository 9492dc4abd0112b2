#pragma once
// A responder's alarm: raised by the device (motionless, mayday) or by incident command (link
// lost, map error), with where the responder was last known to be.
#include <cstdint>
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::responder {

enum class AlarmKind : std::uint8_t {
  kMotionless = 0,  ///< no motion for the configured time (a PASS device's alarm)
  kMayday = 1,      ///< raised by the firefighter
  kLinkLost = 2,    ///< incident command stopped hearing the responder
  kMapError = 3,    ///< the map-aided filter suspects the floor plan is wrong here
};

/// "motionless", "mayday", "link_lost", "map_error".
const char* to_string(AlarmKind kind);
/// What a commander reads: "Motionless", "MAYDAY", "Link lost", "Off the map".
const char* display_name(AlarmKind kind);

struct ResponderAlarm {
  std::string responder_id;
  std::string team_id;
  AlarmKind kind = AlarmKind::kMotionless;
  TimestampNs raised_at = 0;     ///< when the condition began (device or mission time)
  TimestampNs cleared_at = 0;    ///< 0 while active
  bool active = true;
  GaussianPosition last_position;  ///< incident frame (ENU, m); covariance 0: unknown
  bool position_known = false;
  std::int32_t floor = 0;
};

}  // namespace sarloc::responder
