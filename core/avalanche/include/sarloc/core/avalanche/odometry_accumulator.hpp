#pragma once
// Accumulates odometry samples that arrive between two field measurements into one
// displacement d = [t; dPsi] of R_k in R_{k-1} with its 6x6 covariance Q_k (seed 000, eq. (4)).
// Samples are composed in order (compose_displacements) and their covariances propagated with
// the composition Jacobians. When no sample arrived, take() returns a zero displacement with the
// configured idle covariance (the rescuer may still have moved a little).
//
//   OdometryAccumulator acc;   acc.add(odo);   auto [d, q] = acc.take();
#include <cstdint>
#include <optional>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/responder_types.hpp"

namespace sarloc::avalanche {

struct Displacement {
  DispVec mean = DispVec::Zero();
  DispCov covariance = DispCov::Zero();
  std::uint32_t samples = 0;
};

class OdometryAccumulator {
 public:
  OdometryAccumulator(double idle_translation_sigma_m = 0.02, double idle_rotation_sigma_rad = 0.005);

  /// Validates (finite, |t| <= 50 m, |angles| <= pi, covariance symmetric positive definite,
  /// sequence increasing) and composes. Throws InputError naming the field.
  void add(const Odometry& odometry);
  /// Motion that happened but was never measured (odometry lost or late): a zero displacement
  /// with this covariance, composed like a sample; no sequence number. Throws InputError if the
  /// covariance is not finite, symmetric positive definite with variances <= 100.
  void add_unknown(const DispCov& covariance);
  /// The displacement since the last take(), then resets.
  Displacement take();
  /// What take() would return now (the idle displacement when nothing arrived), no reset.
  Displacement pending_displacement() const;
  std::uint32_t pending() const { return acc_.samples; }
  /// What take() would return now, without resetting (zero mean when nothing arrived).
  const Displacement& peek() const { return acc_; }

 private:
  void compose(const DispVec& d, const DispCov& covariance);

  double idle_translation_sigma_m_;
  double idle_rotation_sigma_rad_;
  Displacement acc_;
  std::optional<std::uint64_t> last_sequence_;
};

}  // namespace sarloc::avalanche
