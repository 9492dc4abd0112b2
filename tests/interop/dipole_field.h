#ifndef SARLOC_INTEROP_DIPOLE_FIELD_H
#define SARLOC_INTEROP_DIPOLE_FIELD_H
/* The field an avalanche transceiver measures, written from docs/topics.md alone (not from
 * sarloc's code), so the publish test also checks that the documented conventions are the
 * ones the daemon uses:
 *   H = (3 (m.r) r - r^2 m) / (4 pi r^5),  r = receiver - transmitter (ENU, m), m in A m^2;
 *   measured in the receiver frame R (x forward, y left, z up): H_R = Rot^T H, with
 *   Rot = Rz(yaw) Ry(pitch) Rx(roll) the orientation of R in ENU. */
#include "common.h"

struct sarloc_Vector3 dipole_field(const struct sarloc_Vector3* r, const struct sarloc_Vector3* m);

/* v (in ENU) expressed in the frame whose orientation in ENU is rpy (roll, pitch, yaw). */
struct sarloc_Vector3 to_frame(const struct sarloc_Vector3* rpy, const struct sarloc_Vector3* v);

double vector3_norm(const struct sarloc_Vector3* v);

/* a in (-pi, pi]. */
double wrap_angle(double a);

#endif
