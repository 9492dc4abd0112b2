#pragma once
// Which buried victim a FOUND names (simulation truth, for scoring): one rule for the
// multiple-burial evaluation and the live mission's device summaries.
#include <cstddef>
#include <optional>
#include <vector>

#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

/// A FOUND farther than its stated 95 % 3-D radius plus this margin (m) from the true victim is
/// a false FOUND (the margin is the found distance: the rescuer stands within it).
inline constexpr double kFalseFoundMarginM = 0.5;

/// How far from a FOUND a victim may lie and be the one it names: the stated 95 % 3-D radius
/// plus kFalseFoundMarginM.
double found_reach(const Mat3& covariance);

/// The signal's own transmitter (`own`: the one most of its pulses came from) when it lies within
/// `reach` of the FOUND at `found`, else the nearest victim that does; nullopt when none does, a
/// FOUND near no victim (a ghost). `victims` are in the frame of `found`. Two victims 0.3 m apart,
/// each found by its own signal, are two victims found; a signal whose pulses were another
/// transmitter's at first, and which found the transmitter it followed, found that one (seen live:
/// scored by its first pulse, a FOUND with a 0.30 m radius counted 3.39 m off victim C, about
/// the distance from C to victim A, while the picture had all four victims right).
std::optional<std::size_t> victim_of_found(const Vec3& found, double reach, const std::vector<Vec3>& victims,
                                           std::optional<std::size_t> own);

}  // namespace sarloc::avalanche
