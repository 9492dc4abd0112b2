#include "sarloc/core/responder/victim_estimate.hpp"

namespace sarloc::responder {

const char* to_string(RepeatState state) {
  switch (state) {
    case RepeatState::kNone: return "none";
    case RepeatState::kSuspected: return "suspected";
    case RepeatState::kConfirmed: return "confirmed";
  }
  return "none";
}

}  // namespace sarloc::responder
