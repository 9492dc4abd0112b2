#define _POSIX_C_SOURCE 200809L
#include "value_checks.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

/* Stamps of this run: sarloc-mission's clock starts at its start and runs `speedup` times
 * faster than the wall (docs/topics.md, MissionClock), so stamps may lead the wall clock by
 * minutes; an hour either way is far beyond any mission here, and far inside the gross errors
 * this catches (0, seconds taken for nanoseconds, garbage bytes). */
static const int64_t kStampWindowNs = 3600LL * 1000000000LL;

/* Printed failures are capped so one broken field cannot flood the log. */
enum { kMaxPrinted = 40 };
static int printed = 0;

int64_t wall_now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

CheckReport check_begin(const char* topic) {
  CheckReport r;
  r.topic = topic;
  r.sample[0] = '\0';
  r.failures = 0;
  return r;
}

void check_fail(CheckReport* r, const char* field, const char* fmt, ...) {
  r->failures++;
  if (printed >= kMaxPrinted) return;
  if (++printed == kMaxPrinted) fprintf(stderr, "(further failures not printed)\n");
  fprintf(stderr, "FAIL %s [%s]: %s = ", r->topic, r->sample, field);
  va_list args;
  va_start(args, fmt);
  vfprintf(stderr, fmt, args);
  va_end(args);
  fputc('\n', stderr);
}

void check_finite(CheckReport* r, const char* field, double value) {
  if (!isfinite(value)) check_fail(r, field, "%g: must be finite", value);
}

void check_range(CheckReport* r, const char* field, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi)) check_fail(r, field, "%.9g: must be in [%g, %g]", value, lo, hi);
}

void check_angle(CheckReport* r, const char* field, double value) {
  const double pi = 3.14159265358979323846;
  check_range(r, field, value, -pi - 1e-9, pi + 1e-9);
}

void check_enum(CheckReport* r, const char* field, uint32_t value, uint32_t last) {
  if (value > last) check_fail(r, field, "%u: unknown enumerator (last is %u)", value, last);
}

static size_t bounded_length(const char* s, size_t capacity) {
  const char* end = memchr(s, '\0', capacity);
  return end == NULL ? capacity : (size_t)(end - s);
}

void check_id(CheckReport* r, const char* field, const char* id, size_t capacity) {
  const size_t n = bounded_length(id, capacity);
  if (n == capacity) {
    check_fail(r, field, "(unterminated): must end within %zu bytes", capacity);
    return;
  }
  if (n == 0) check_fail(r, field, "'': must not be empty");
  for (size_t i = 0; i < n; ++i) {
    if (!isprint((unsigned char)id[i])) {
      check_fail(r, field, "'%s': byte %zu (0x%02x) is not printable ASCII", id, i, (unsigned char)id[i]);
      return;
    }
  }
}

void check_text(CheckReport* r, const char* field, const char* text, size_t capacity) {
  const size_t n = bounded_length(text, capacity);
  if (n == capacity) {
    check_fail(r, field, "(unterminated): must end within %zu bytes", capacity);
    return;
  }
  for (size_t i = 0; i < n; ++i) {
    const unsigned char c = (unsigned char)text[i];
    if (c < 0x20 || c == 0x7f) {
      check_fail(r, field, "byte %zu (0x%02x) is a control character", i, c);
      return;
    }
  }
}

void check_stamp(CheckReport* r, const char* field, int64_t stamp_ns) {
  const int64_t now = wall_now_ns();
  if (stamp_ns < now - kStampWindowNs || stamp_ns > now + kStampWindowNs) {
    check_fail(r, field, "%lld ns: must be within an hour of now (%lld ns)", (long long)stamp_ns, (long long)now);
  }
}

void check_stamp_or_zero(CheckReport* r, const char* field, int64_t stamp_ns) {
  if (stamp_ns != 0) check_stamp(r, field, stamp_ns);
}

void check_vector3(CheckReport* r, const char* field, const struct sarloc_Vector3* v, double max_norm) {
  if (!isfinite(v->x) || !isfinite(v->y) || !isfinite(v->z)) {
    check_fail(r, field, "(%g, %g, %g): must be finite", v->x, v->y, v->z);
    return;
  }
  const double norm = sqrt(v->x * v->x + v->y * v->y + v->z * v->z);
  if (norm > max_norm) check_fail(r, field, "(%g, %g, %g): norm %g exceeds %g", v->x, v->y, v->z, norm, max_norm);
}

void check_covariance(CheckReport* r, const char* field, const double* m, int n) {
  for (int i = 0; i < n * n; ++i) {
    if (!isfinite(m[i])) {
      check_fail(r, field, "element [%d][%d] = %g: must be finite", i / n, i % n, m[i]);
      return;
    }
  }
  for (int i = 0; i < n; ++i) {
    if (m[i * n + i] < 0.0) check_fail(r, field, "diagonal [%d][%d] = %g: must be >= 0", i, i, m[i * n + i]);
    for (int j = i + 1; j < n; ++j) {
      const double a = m[i * n + j];
      const double b = m[j * n + i];
      const double scale = fmax(1e-300, fmax(fabs(a), fabs(b)));
      if (fabs(a - b) > 1e-9 * scale) {
        check_fail(r, field, "[%d][%d] = %.17g but [%d][%d] = %.17g: must be symmetric", i, j, a, j, i, b);
      }
    }
  }
}

void check_position(CheckReport* r, const char* field, const struct sarloc_PositionWithCovariance* p) {
  char name[96];
  snprintf(name, sizeof name, "%s.position", field);
  /* An incident is a few km across at most. */
  check_vector3(r, name, &p->position, 1e4);
  snprintf(name, sizeof name, "%s.covariance", field);
  check_covariance(r, name, p->covariance, 3);
}

void check_below(CheckReport* r, const char* field, const struct sarloc_PositionWithCovariance* p, double ceiling_m) {
  const double sigma_z = sqrt(fmax(0.0, p->covariance[8]));
  if (!(p->position.z - 3.0 * sigma_z <= ceiling_m)) {
    check_fail(r, field, "z %.3f m (sigma %.3f m): a buried victim must lie below %.1f m", p->position.z, sigma_z,
               ceiling_m);
  }
}
