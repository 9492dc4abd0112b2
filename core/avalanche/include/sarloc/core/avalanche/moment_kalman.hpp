#pragma once
// The Kalman filter on the magnetic moment given the receiver's attitude and the transmitter's
// position (seed 000, Algorithm 3): the measurement z = R_k^T H(-p, m) = C m is linear in m,
// C = R_k^T (3 u u^T - I) / (4 pi r^3), u = -p / r (eq. (12)-(14) with d = 0), so the update is
// exact. Shared by the Rao-Blackwellized particle filter (one per particle) and the grid filter
// (one per cell).
//
//   const Mat3 c = moment_gain(rotation_from_rpy(psi), p);
//   MomentUpdate u = update_moment(c, m, M, z_valid, floor, axes, sog.noise());
#include <cstdint>

#include "sarloc/core/avalanche/field_noise_model.hpp"
#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

/// C = dz/dm for a receiver with attitude `rotation` (R_k in G_k) and a transmitter at p (G_k).
/// p must be non-zero.
Mat3 moment_gain(const Mat3& rotation, const Vec3& p);

struct MomentUpdate {
  bool ok = false;   ///< false: the innovation covariance was not positive definite (m, M unchanged)
  double ll = 0.0;   ///< log of the sign-invariant predictive likelihood, common constants dropped
  double nis = 0.0;  ///< normalised innovation squared for the sign that explains z best
  Vec3 predicted = Vec3::Zero();       ///< C m before the update (invalid axes 0)
  Mat3 innovation_covariance = Mat3::Identity();  ///< S (invalid axes: 1 on the diagonal)
};

/// The moment-matched predictive distribution of a weighted cloud of hypotheses (particles,
/// cells): z ~ N(sum w h_i, sum w (S_i + h_i h_i^T) - zbar zbar^T). Its NIS is the cloud's
/// consistency with a sample; the smallest NIS over point particles is not (thousands of points
/// always hold one that fits). Each hypothesis's MomentUpdate is added with its prior weight.
class PredictiveMoments {
 public:
  void add(double weight, const MomentUpdate& u);
  /// NIS of z (invalid axes zeroed) under the sign that fits best; 0 when nothing was added.
  double nis(const Vec3& z_valid) const;

 private:
  double weight_ = 0.0;
  Vec3 mean_ = Vec3::Zero();
  Mat3 second_ = Mat3::Zero();
};

/// One sample z (invalid axes zeroed: z_valid) with per-axis noise relative |C m| + floor:
/// S = C M C^T + R, p(z) = (N(z; C m, S) + N(-z; C m, S)) / 2; m and M are updated with the
/// sign that explains z best (as the SOG filter does). M = 0 gives the point likelihood of a
/// particle that samples m.
MomentUpdate update_moment(const Mat3& gain, Vec3& m, Mat3& M, const Vec3& z_valid, const Vec3& floor,
                           std::uint8_t axes, const FieldNoiseModel& noise);


}  // namespace sarloc::avalanche
