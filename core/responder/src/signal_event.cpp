#include "sarloc/core/responder/signal_event.hpp"

namespace sarloc::responder {

const char* to_string(SignalEvent event) {
  switch (event) {
    case SignalEvent::kNone: return "none";
    case SignalEvent::kNew: return "new";
    case SignalEvent::kReacquired: return "reacquired";
    case SignalEvent::kSeparated: return "separated";
  }
  return "none";
}

}  // namespace sarloc::responder
