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

}  // namespace sarloc::responder
