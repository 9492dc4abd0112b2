#pragma once
// Which buried victim a FOUND names (simulation truth, for scoring): victim_of_found for one
// FOUND (the live mission's device summaries), match_founds for a search's FOUNDs together (the
// multiple-burial evaluation), built on it.
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

/// One FOUND of a search, in the victims' frame.
struct FoundClaim {
  Vec3 position = Vec3::Zero();
  Mat3 covariance = Mat3::Identity();  ///< its stated uncertainty
  std::optional<std::size_t> own;      ///< the transmitter most of its signal's pulses came from
};

/// The victims a search's FOUNDs name, one FOUND per victim. A FOUND may name the victim
/// victim_of_found gives, and any victim inside its stated 95 % 3-D radius: the spot it claims.
/// The FOUNDs are matched to distinct victims, as many as can be (augmenting paths, each FOUND's
/// victim_of_found tried first). Why: two victims 0.3 m apart, both transmitters' pulses mixed
/// in one signal, whose FOUND lay 0.10 m from the victim no other signal found, inside its 0.15 m
/// radius, and 0.29 m from the one it shared most pulses with, which its own signal had found
/// 0.01 m off: both victims found, not one twice (4 victims, seed 6, trial 36).
struct FoundMatching {
  std::vector<std::optional<std::size_t>> victim;  ///< per FOUND; nullopt: a ghost or a repeat
  std::size_t found = 0;       ///< distinct victims named
  std::size_t ghosts = 0;      ///< FOUNDs that name no victim
  std::size_t duplicates = 0;  ///< FOUNDs naming only victims other FOUNDs name
};
FoundMatching match_founds(const std::vector<FoundClaim>& founds, const std::vector<Vec3>& victims);

}  // namespace sarloc::avalanche
