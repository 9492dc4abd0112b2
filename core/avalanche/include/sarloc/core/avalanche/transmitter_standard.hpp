#pragma once
// Moment bounds of an avalanche beacon from the EN 300 718 field-strength limits.
//
// The standard (as quoted by PIEPS, /work/shared/NOTES.md) bounds the field strength at 10 m
// to 0.5 ... 2.23 uA/m. We read it as the weakest direction of the dipole, the equatorial
// plane, where |H| = m / (4 pi r^3): m = 4 pi r^3 |H| gives m_min = 6.28e-3 A m^2 and
// m_max = 2.80e-2 A m^2 at r = 10 m. (The on-axis field is twice as strong.)
#include <string>

#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

struct TransmitterStandard {
  double field_min_A_per_m = 0.5e-6;   ///< EN 300 718 lower field-strength limit at reference
  double field_max_A_per_m = 2.23e-6;  ///< EN 300 718 upper field-strength limit at reference
  double reference_distance_m = 10.0;  ///< distance at which the limits apply

  double moment_min() const;  ///< A m^2, equatorial convention
  double moment_max() const;  ///< A m^2, equatorial convention
  /// On-axis field of the strongest admissible transmitter at distance r (A/m).
  double strongest_on_axis_field(double r) const;

  /// A moment estimate (mean, covariance) whose magnitude may lie within [moment_min, moment_max]
  /// widened by `margin` (relative), at 2 sigma along its mean: an estimate needing a
  /// transmitter the standard does not allow is wrong (seen: a FOUND 1.8 m off with |m| 8x the
  /// largest allowed).
  bool allows(const Vec3& moment, const Mat3& covariance, double margin) const;

  /// Throws ConfigError naming `<prefix>.<field> = value: rule`.
  void validate(const std::string& prefix) const;
};

}  // namespace sarloc::avalanche
