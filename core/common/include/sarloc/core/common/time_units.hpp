#pragma once
// Seconds (config, physics) <-> nanoseconds (TimestampNs, the wire). Truncates toward zero,
// as every conversion written out by hand before it did.
#include "sarloc/core/common/types.hpp"

namespace sarloc {

inline constexpr TimestampNs kNsPerSecond = 1'000'000'000;

constexpr TimestampNs seconds_to_ns(double seconds) { return static_cast<TimestampNs>(seconds * 1e9); }
constexpr double ns_to_seconds(TimestampNs ns) { return static_cast<double>(ns) / 1e9; }

}  // namespace sarloc
