#include "sarloc/core/responder/alarm.hpp"

namespace sarloc::responder {

const char* to_string(AlarmKind kind) {
  switch (kind) {
    case AlarmKind::kMotionless: return "motionless";
    case AlarmKind::kMayday: return "mayday";
    case AlarmKind::kLinkLost: return "link_lost";
    case AlarmKind::kMapError: return "map_error";
  }
  return "unknown";
}

const char* display_name(AlarmKind kind) {
  switch (kind) {
    case AlarmKind::kMotionless: return "Motionless";
    case AlarmKind::kMayday: return "MAYDAY";
    case AlarmKind::kLinkLost: return "Link lost";
    case AlarmKind::kMapError: return "Off the map";
  }
  return "Unknown alarm";
}

}  // namespace sarloc::responder
