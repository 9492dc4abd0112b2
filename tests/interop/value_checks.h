#ifndef SARLOC_INTEROP_VALUE_CHECKS_H
#define SARLOC_INTEROP_VALUE_CHECKS_H
/* Checks of single values received from sarloc over another vendor's DDS. Each failed check
 * prints one line naming the topic, the field, the value and the rule broken, e.g.
 *   FAIL sarloc/guidance [rescuer 'r1' seq 7]: bearing_rad = nan: must be finite
 * and counts the failure in the report of the sample being checked.
 *
 *   CheckReport r = check_begin("sarloc/guidance");
 *   check_angle(&r, "bearing_rad", g->bearing_rad);
 *   if (r.failures > 0) ...
 */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "common.h"

typedef struct CheckReport {
  const char* topic; /* sarloc/... */
  char sample[128];  /* which sample (its key), set by the caller for the messages */
  int failures;      /* failed checks of this sample */
} CheckReport;

CheckReport check_begin(const char* topic);

/* Records a failure: "FAIL <topic> [<sample>]: <field> = <printf text>". */
void check_fail(CheckReport* r, const char* field, const char* fmt, ...) __attribute__((format(printf, 3, 4)));

void check_finite(CheckReport* r, const char* field, double value);
void check_range(CheckReport* r, const char* field, double value, double lo, double hi);
/* A wrapped angle: finite, in [-pi, pi]. */
void check_angle(CheckReport* r, const char* field, double value);
void check_enum(CheckReport* r, const char* field, uint32_t value, uint32_t last);
/* An Identifier: 1..ID_MAX printable ASCII characters, NUL-terminated within `capacity`. */
void check_id(CheckReport* r, const char* field, const char* id, size_t capacity);
/* Free text: printable (UTF-8 bytes allowed), NUL-terminated within `capacity`; may be empty. */
void check_text(CheckReport* r, const char* field, const char* text, size_t capacity);
/* A TimeNs of this run (see check_stamp_window in value_checks.c). */
void check_stamp(CheckReport* r, const char* field, int64_t stamp_ns);
/* A TimeNs that is 0 while an event has not happened, else a stamp of this run. */
void check_stamp_or_zero(CheckReport* r, const char* field, int64_t stamp_ns);
/* Finite, and |v| <= max_norm. */
void check_vector3(CheckReport* r, const char* field, const struct sarloc_Vector3* v, double max_norm);
/* n x n row-major: finite, symmetric, non-negative diagonal. */
void check_covariance(CheckReport* r, const char* field, const double* m, int n);
/* position.z is at most 3 sigma above `ceiling_m` (a victim below the surface or the antenna). */
void check_below(CheckReport* r, const char* field, const struct sarloc_PositionWithCovariance* p, double ceiling_m);
void check_position(CheckReport* r, const char* field, const struct sarloc_PositionWithCovariance* p);

/* Wall clock now, ns since the Unix epoch. */
int64_t wall_now_ns(void);

#endif
