#pragma once
// Rescuer-relative victim estimate -> incident frame.
//
// A rescuer's filter estimates the victim in G_k: centred on the receiver antenna at time k,
// axis-aligned with the incident ENU frame (common/types.hpp). The incident-frame position is
// therefore a pure translation by the antenna position at the same instant:
//
//   p_I = p_antenna + p_rel,        P_I = P_rel + P_antenna.
//
// The covariance sum assumes the two errors are independent: p_rel comes from the magnetic
// field and odometry, p_antenna from GNSS (or the responder localisation), so they share no
// measurement. It is exact for a pure translation (Jacobians are identities). What is NOT
// independent is the error of two estimates that use the same rescuer's antenna position: every
// signal of one rescuer carries the same GNSS bias. VictimFusion uses covariance intersection
// for that reason (covariance_intersection.hpp).
//
// The caller must give the antenna position at the estimate's stamp (interpolate the responder
// track; a lag dt at walking speed v adds v * dt of error that is in neither covariance), and
// the antenna, not the GNSS receiver's body, if a lever arm matters.
//
//   GaussianPosition victim_I = to_incident_frame(estimate.relative, antenna_at(estimate.stamp));
#include "sarloc/core/common/types.hpp"

namespace sarloc::incident {

/// p = p_rescuer + p_rel, P = P_rel + P_rescuer (independent errors, see above).
GaussianPosition to_incident_frame(const GaussianPosition& relative,
                                   const GaussianPosition& rescuer_antenna);

}  // namespace sarloc::incident
