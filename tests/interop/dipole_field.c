#include "dipole_field.h"

#include <math.h>

static const double kPi = 3.14159265358979323846;

double vector3_norm(const struct sarloc_Vector3* v) { return sqrt(v->x * v->x + v->y * v->y + v->z * v->z); }

struct sarloc_Vector3 dipole_field(const struct sarloc_Vector3* r, const struct sarloc_Vector3* m) {
  const double r2 = r->x * r->x + r->y * r->y + r->z * r->z;
  const double r5 = r2 * r2 * sqrt(r2);
  const double m_dot_r = m->x * r->x + m->y * r->y + m->z * r->z;
  const double k = 1.0 / (4.0 * kPi * r5);
  struct sarloc_Vector3 h = {k * (3.0 * m_dot_r * r->x - r2 * m->x), k * (3.0 * m_dot_r * r->y - r2 * m->y),
                             k * (3.0 * m_dot_r * r->z - r2 * m->z)};
  return h;
}

struct sarloc_Vector3 to_frame(const struct sarloc_Vector3* rpy, const struct sarloc_Vector3* v) {
  const double cr = cos(rpy->x), sr = sin(rpy->x);
  const double cp = cos(rpy->y), sp = sin(rpy->y);
  const double cy = cos(rpy->z), sy = sin(rpy->z);
  /* Rows of Rot^T are the columns of Rot = Rz(yaw) Ry(pitch) Rx(roll). */
  const double rot[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                            {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                            {-sp, cp * sr, cp * cr}};
  struct sarloc_Vector3 out = {rot[0][0] * v->x + rot[1][0] * v->y + rot[2][0] * v->z,
                               rot[0][1] * v->x + rot[1][1] * v->y + rot[2][1] * v->z,
                               rot[0][2] * v->x + rot[1][2] * v->y + rot[2][2] * v->z};
  return out;
}

double wrap_angle(double a) {
  a = fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) a += 2.0 * kPi;
  return a - kPi;
}
