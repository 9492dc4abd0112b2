#ifndef SARLOC_INTEROP_SAMPLE_CHECKS_H
#define SARLOC_INTEROP_SAMPLE_CHECKS_H
/* What a sample of each sarloc topic must hold (units, frames and bounds of docs/topics.md):
 * finite numbers, ids within bounds, known enumerators, symmetric covariances with a
 * non-negative diagonal, stamps of this run, sequence numbers increasing per instance, and
 * located victims below the surface. Each takes the idlc-generated C type. */
#include "value_checks.h"

void check_field_measurement(const void* sample, CheckReport* r);
void check_odometry(const void* sample, CheckReport* r);
void check_victim_estimate(const void* sample, CheckReport* r);
void check_guidance(const void* sample, CheckReport* r);
void check_responder_position(const void* sample, CheckReport* r);
void check_incident_frame(const void* sample, CheckReport* r);
void check_fused_victim(const void* sample, CheckReport* r);
void check_team_status(const void* sample, CheckReport* r);
void check_incident_summary(const void* sample, CheckReport* r);
void check_node_status(const void* sample, CheckReport* r);

#endif
