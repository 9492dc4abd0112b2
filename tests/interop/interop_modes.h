#ifndef SARLOC_INTEROP_INTEROP_MODES_H
#define SARLOC_INTEROP_INTEROP_MODES_H
/* The two halves of the Cyclone DDS interoperability test (docs/topics.md, "Interoperability
 * with other DDS vendors"). Both return an exit code: 0 passed, 1 a check failed, 4 could not
 * run (DDS entities). */
#include <signal.h>
#include <stdint.h>

typedef struct InteropOptions {
  uint32_t domain;
  double timeout_s;        /* subscribe: stop after this long; publish: wait this long for the daemon */
  int min_samples;         /* subscribe: valid samples each topic must deliver */
  const char* rescuer_id;  /* publish: the rescuer this program pretends to be */
  int epochs;              /* publish: measurement epochs along the walked path */
  double answer_timeout_s; /* publish: wait for the daemon's answer to one epoch */
} InteropOptions;

enum { kExitOk = 0, kExitFailed = 1, kExitUsage = 2, kExitCannotRun = 4 };

/* Set by SIGINT / SIGTERM: subscribe mode then stops and reports. */
extern volatile sig_atomic_t interop_stop_requested;

/* Subscribes to every sarloc topic until stopped or timed out, checks every sample, and fails
 * on a bad value or on a topic that delivered fewer than min_samples valid samples. */
int run_subscribe(const InteropOptions* options);

/* Publishes FieldMeasurement and Odometry of one rescuer walking near a transmitter and fails
 * unless the core daemon answers every epoch (VictimEstimate and Guidance with its sequence). */
int run_publish(const InteropOptions* options);

#endif
