#pragma once
// The field measurement's noise, one model for every estimator of it (seed 000, eq. (14):
// z = h(x, d) + n). Per axis, sigma = relative * |field| + floor: a part relative to the field
// (receiver gain, pointing, the dipole model's idealisation) and the device's own floor, never
// below the model's. |field| is the predicted field where a filter has one (every update), the
// measured one where it has not (the initial ring, the search controller's SNR, the simulator's
// draw). The SOG filter, the particle and grid baselines, the lookahead and the search
// controller take it from SogConfig::noise(), the simulator from SimulationConfig::field_noise().
//
//   const FieldNoiseModel noise = sog.noise();
//   const Vec3 floor = noise.floor(measurement.noise_stddev);
//   const Vec3 sigma = noise.sigma(h.norm(), floor);
#include <cstdint>

#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

struct FieldNoiseModel {
  double relative = 0.05;         ///< of |field|, per axis
  double floor_A_per_m = 2.1e-9;  ///< no axis of any measurement is less noisy than this (A/m)

  /// A measurement's per-axis floor: what its device states, at least the model's.
  Vec3 floor(const Vec3& device_noise) const { return device_noise.cwiseMax(floor_A_per_m); }
  /// Per-axis sigma of a field of magnitude `field_norm` over the per-axis `floor`.
  Vec3 sigma(double field_norm, const Vec3& floor) const { return Vec3::Constant(relative * field_norm) + floor; }
  double sigma(double field_norm, double floor) const { return relative * field_norm + floor; }
  /// Over the model's own floor (the simulator's draw).
  double sigma(double field_norm) const { return sigma(field_norm, floor_A_per_m); }
};

/// `z` with every axis not in `axes` (bit a: axis a heard) set to zero: an axis below the
/// detection threshold observes nothing, and every filter treats it so.
inline Vec3 valid_axes_only(const Vec3& z, std::uint8_t axes) {
  Vec3 out = z;
  for (int a = 0; a < 3; ++a)
    if ((axes & (1U << a)) == 0) out[a] = 0.0;
  return out;
}

}  // namespace sarloc::avalanche
