#pragma once
// What a detector's signal separation says about one of its signals (one victim's beacon): the
// device's samples carry it, the victim estimate keeps the last one, incident command shows it.
// A merged, lost or swapped signal is thus visible wherever the victim is.
#include <cstdint>

namespace sarloc::responder {

enum class SignalEvent : std::uint8_t {
  kNone = 0,        ///< tracked as before
  kNew,             ///< first sample of a newly separated transmitter
  kReacquired,      ///< heard again after the separation had declared it lost
  kSeparated,       ///< attributed again after its pulses merged with another transmitter's
};
/// "none", "new", "reacquired", "separated".
const char* to_string(SignalEvent event);

}  // namespace sarloc::responder
