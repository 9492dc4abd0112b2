#include "sample_checks.h"

#include <stdio.h>
#include <string.h>

#include "avalanche.h"
#include "responder.h"
#include "incident.h"
#include "status.h"

/* Gross bounds: anything past them is a decoding error, not a measurement. A transmitter of
 * EN 300 718 (moment <= 0.03 A m^2) gives about 1 A/m at 0.2 m; one walked step is a few m. */
#define MAX_FIELD_A_PER_M 10.0
#define MAX_MOMENT_A_M2 1.0
#define MAX_STEP_M 100.0
#define MAX_DISTANCE_M 1e4

/* sequence numbers seen per (topic, id, signal): strictly increasing per writer instance. */
typedef struct SequenceTrack {
  const char* topic;
  char id[sarloc_ID_MAX + 1];
  uint32_t signal;
  uint64_t last;
} SequenceTrack;

enum { kMaxTracks = 512 };
static SequenceTrack tracks[kMaxTracks];
static int track_count = 0;

static void check_sequence_increases(CheckReport* r, const char* field, const char* id, uint32_t signal,
                                     uint64_t sequence) {
  if (sequence == 0) {
    check_fail(r, field, "0: sequences start at 1");
    return;
  }
  for (int i = 0; i < track_count; ++i) {
    SequenceTrack* t = &tracks[i];
    if (t->topic == r->topic && t->signal == signal && strncmp(t->id, id, sizeof t->id) == 0) {
      if (sequence <= t->last) {
        check_fail(r, field, "%llu after %llu: must increase strictly", (unsigned long long)sequence,
                   (unsigned long long)t->last);
      }
      t->last = sequence;
      return;
    }
  }
  if (track_count == kMaxTracks) return; /* more instances than any test mission has */
  SequenceTrack* t = &tracks[track_count++];
  t->topic = r->topic;
  snprintf(t->id, sizeof t->id, "%s", id);
  t->signal = signal;
  t->last = sequence;
}

static void check_orientation(CheckReport* r, const struct sarloc_Vector3* rpy) {
  check_angle(r, "orientation_rpy.x (roll)", rpy->x);
  check_angle(r, "orientation_rpy.y (pitch)", rpy->y);
  check_angle(r, "orientation_rpy.z (yaw)", rpy->z);
}

void check_field_measurement(const void* sample, CheckReport* r) {
  const sarloc_FieldMeasurement* m = sample;
  snprintf(r->sample, sizeof r->sample, "rescuer '%.64s' signal %u seq %llu", m->rescuer_id, m->signal_id,
           (unsigned long long)m->sequence_number);
  check_id(r, "rescuer_id", m->rescuer_id, sizeof m->rescuer_id);
  check_sequence_increases(r, "sequence_number", m->rescuer_id, m->signal_id, m->sequence_number);
  check_stamp(r, "stamp", m->stamp);
  check_vector3(r, "field", &m->field, MAX_FIELD_A_PER_M);
  check_vector3(r, "noise_stddev", &m->noise_stddev, MAX_FIELD_A_PER_M);
  if (m->noise_stddev.x < 0.0 || m->noise_stddev.y < 0.0 || m->noise_stddev.z < 0.0) {
    check_fail(r, "noise_stddev", "(%g, %g, %g): a standard deviation must be >= 0", m->noise_stddev.x,
               m->noise_stddev.y, m->noise_stddev.z);
  }
  if (m->valid_axes > 7) check_fail(r, "valid_axes", "%u: a mask of bits 0-2 (0: a pulse due, not heard)", m->valid_axes);
  if (m->valid_axes == 0 && (m->noise_stddev.x <= 0.0 || m->noise_stddev.y <= 0.0 || m->noise_stddev.z <= 0.0))
    check_fail(r, "noise_stddev", "a miss (valid_axes 0) carries its pulse floor: every axis > 0");
  check_enum(r, "signal_event", m->signal_event, sarloc_SIGNAL_SEPARATED);
  if (m->has_orientation) {
    check_orientation(r, &m->orientation_rpy);
    check_covariance(r, "orientation_covariance", m->orientation_covariance, 3);
  }
}

void check_odometry(const void* sample, CheckReport* r) {
  const sarloc_Odometry* o = sample;
  snprintf(r->sample, sizeof r->sample, "rescuer '%.64s' seq %llu", o->rescuer_id,
           (unsigned long long)o->sequence_number);
  check_id(r, "rescuer_id", o->rescuer_id, sizeof o->rescuer_id);
  check_sequence_increases(r, "sequence_number", o->rescuer_id, 0, o->sequence_number);
  check_stamp(r, "interval_start", o->interval_start);
  check_stamp(r, "interval_end", o->interval_end);
  if (o->interval_end < o->interval_start) {
    check_fail(r, "interval_end", "%lld: before interval_start %lld", (long long)o->interval_end,
               (long long)o->interval_start);
  }
  check_vector3(r, "translation", &o->translation, MAX_STEP_M);
  check_angle(r, "rotation_rpy.x (roll)", o->rotation_rpy.x);
  check_angle(r, "rotation_rpy.y (pitch)", o->rotation_rpy.y);
  check_angle(r, "rotation_rpy.z (yaw)", o->rotation_rpy.z);
  check_covariance(r, "covariance", o->covariance, 6);
  check_enum(r, "source", o->source, sarloc_ODOMETRY_OTHER);
}

static void check_components(CheckReport* r, const sarloc_VictimEstimate* e) {
  const dds_sequence_sarloc_MixtureComponent* c = &e->top_components;
  if (c->_length > sarloc_MIXTURE_SUMMARY_MAX) {
    check_fail(r, "top_components", "%u components: at most %u", c->_length, sarloc_MIXTURE_SUMMARY_MAX);
    return;
  }
  if (c->_length > e->live_components) {
    check_fail(r, "live_components", "%u: fewer than the %u top components", e->live_components, c->_length);
  }
  double sum = 0.0;
  char field[64];
  for (uint32_t i = 0; i < c->_length; ++i) {
    const struct sarloc_MixtureComponent* k = &c->_buffer[i];
    snprintf(field, sizeof field, "top_components[%u].weight", i);
    check_range(r, field, k->weight, 0.0, 1.0 + 1e-9); /* normalised, up to rounding */
    if (i > 0 && k->weight > c->_buffer[i - 1].weight) {
      check_fail(r, field, "%g: heavier than the component before (%g), must be heaviest first", k->weight,
                 c->_buffer[i - 1].weight);
    }
    sum += k->weight;
    snprintf(field, sizeof field, "top_components[%u].mean", i);
    check_vector3(r, field, &k->mean, MAX_DISTANCE_M);
    snprintf(field, sizeof field, "top_components[%u].covariance", i);
    check_covariance(r, field, k->covariance, 3);
  }
  if (sum > 1.0 + 1e-9) check_fail(r, "top_components[].weight", "sum %.9g: normalised weights sum to <= 1", sum);
}

void check_victim_estimate(const void* sample, CheckReport* r) {
  const sarloc_VictimEstimate* e = sample;
  snprintf(r->sample, sizeof r->sample, "rescuer '%.64s' signal %u seq %llu", e->rescuer_id, e->signal_id,
           (unsigned long long)e->measurement_sequence);
  check_id(r, "rescuer_id", e->rescuer_id, sizeof e->rescuer_id);
  check_stamp(r, "stamp", e->stamp);
  if (e->measurement_sequence == 0) check_fail(r, "measurement_sequence", "0: sequences start at 1");
  check_enum(r, "status", e->status, sarloc_ESTIMATOR_FOUND);
  check_position(r, "relative", &e->relative);
  /* Once located, the victim is below the receiver antenna (mirror solutions above it are
   * never located: docs/estimation/avalanche.md). */
  if (e->status >= sarloc_ESTIMATOR_LOCATED && e->status <= sarloc_ESTIMATOR_FOUND) {
    check_below(r, "relative.position.z", &e->relative, 0.0);
  }
  check_components(r, e);
  check_vector3(r, "moment", &e->moment, MAX_MOMENT_A_M2);
  check_enum(r, "signal_event", e->signal_event, sarloc_SIGNAL_SEPARATED);
  check_stamp_or_zero(r, "signal_event_stamp", e->signal_event_stamp);
  check_enum(r, "repeat", e->repeat, sarloc_REPEAT_CONFIRMED);
  if (e->repeat != sarloc_REPEAT_NONE && e->repeat_of_signal == e->signal_id) {
    check_fail(r, "repeat_of_signal", "%u: a signal cannot repeat itself", e->repeat_of_signal);
  }
  /* A repeat confirms nothing (docs/topics.md). */
  if (e->repeat != sarloc_REPEAT_NONE && e->status > sarloc_ESTIMATOR_CONVERGED) {
    check_fail(r, "status", "%d: a repeat is at most CONVERGED", (int)e->status);
  }
}

void check_guidance(const void* sample, CheckReport* r) {
  const sarloc_Guidance* g = sample;
  snprintf(r->sample, sizeof r->sample, "rescuer '%.64s' signal %u seq %llu", g->rescuer_id, g->signal_id,
           (unsigned long long)g->measurement_sequence);
  check_id(r, "rescuer_id", g->rescuer_id, sizeof g->rescuer_id);
  check_stamp(r, "stamp", g->stamp);
  if (g->measurement_sequence == 0) check_fail(r, "measurement_sequence", "0: sequences start at 1");
  check_enum(r, "mode", g->mode, sarloc_GUIDANCE_FOUND);
  check_angle(r, "bearing_rad", g->bearing_rad);
  check_angle(r, "heading_rad", g->heading_rad);
  check_range(r, "distance_m", g->distance_m, 0.0, MAX_DISTANCE_M);
  check_range(r, "step_m", g->step_m, 0.0, MAX_STEP_M);
  check_range(r, "uncertainty_radius_m", g->uncertainty_radius_m, 0.0, MAX_DISTANCE_M);
}

void check_responder_position(const void* sample, CheckReport* r) {
  const sarloc_ResponderPosition* p = sample;
  snprintf(r->sample, sizeof r->sample, "responder '%.64s'", p->responder_id);
  check_id(r, "responder_id", p->responder_id, sizeof p->responder_id);
  check_id(r, "team_id", p->team_id, sizeof p->team_id);
  check_stamp(r, "stamp", p->stamp);
  check_position(r, "position", &p->position);
  check_angle(r, "heading_rad", p->heading_rad);
  check_range(r, "floor", p->floor, -20, 200);
  check_enum(r, "source", p->source, sarloc_POSITION_MANUAL);
  const uint32_t known =
      sarloc_RESPONDER_FLAG_CONVERGED | sarloc_RESPONDER_FLAG_MAP_ERROR_SUSPECTED | sarloc_RESPONDER_FLAG_CONFIRMED;
  if ((p->flags & ~known) != 0) check_fail(r, "flags", "0x%x: unknown bits (known 0x%x)", p->flags, known);
}

void check_incident_frame(const void* sample, CheckReport* r) {
  const sarloc_IncidentFrame* f = sample;
  snprintf(r->sample, sizeof r->sample, "incident '%.64s'", f->incident_id);
  check_id(r, "incident_id", f->incident_id, sizeof f->incident_id);
  check_range(r, "latitude_deg", f->latitude_deg, -90.0, 90.0);
  check_range(r, "longitude_deg", f->longitude_deg, -180.0, 180.0);
  check_range(r, "altitude_m", f->altitude_m, -500.0, 9000.0);
  check_text(r, "name", f->name, sizeof f->name);
  check_stamp(r, "established", f->established);
}

void check_fused_victim(const void* sample, CheckReport* r) {
  const sarloc_FusedVictim* v = sample;
  snprintf(r->sample, sizeof r->sample, "victim %u", v->victim_id);
  check_position(r, "position", &v->position);
  check_enum(r, "state", v->state, sarloc_VICTIM_RECOVERED);
  check_range(r, "floor", v->floor, -20, 200);
  /* The test mission is an avalanche: buried victims, heights above the snow surface z = 0. */
  if (v->floor == 0 && v->state >= sarloc_VICTIM_LOCATED && v->state <= sarloc_VICTIM_FOUND) {
    check_below(r, "position.z", &v->position, 0.0);
  }
  /* No source is valid: a victim keeps its last fused position when its sources go. */
  if (v->sources._length > sarloc_VICTIM_SOURCES_MAX) {
    check_fail(r, "sources", "%u entries: at most %u", v->sources._length, sarloc_VICTIM_SOURCES_MAX);
  } else {
    char field[64];
    for (uint32_t i = 0; i < v->sources._length; ++i) {
      snprintf(field, sizeof field, "sources[%u].rescuer_id", i);
      check_id(r, field, v->sources._buffer[i].rescuer_id, sizeof v->sources._buffer[i].rescuer_id);
      snprintf(field, sizeof field, "sources[%u].last_update", i);
      check_stamp(r, field, v->sources._buffer[i].last_update);
      snprintf(field, sizeof field, "sources[%u].signal_event", i);
      check_enum(r, field, v->sources._buffer[i].signal_event, sarloc_SIGNAL_SEPARATED);
      snprintf(field, sizeof field, "sources[%u].signal_event_stamp", i);
      check_stamp_or_zero(r, field, v->sources._buffer[i].signal_event_stamp);
    }
  }
  check_stamp(r, "first_seen", v->first_seen);
  check_stamp(r, "last_update", v->last_update);
  if (v->last_update < v->first_seen) {
    check_fail(r, "last_update", "%lld: before first_seen %lld", (long long)v->last_update, (long long)v->first_seen);
  }
  check_stamp_or_zero(r, "located_at", v->located_at);
  check_stamp_or_zero(r, "found_at", v->found_at);
  if (v->possibly_same_as == v->victim_id) {
    check_fail(r, "possibly_same_as", "%u: the victim's own id", v->possibly_same_as);
  }
  if (v->state >= sarloc_VICTIM_LOCATED && v->state <= sarloc_VICTIM_RECOVERED && v->located_at == 0) {
    check_fail(r, "located_at", "0 while state is %u (located or later)", v->state);
  }
  if (v->state >= sarloc_VICTIM_FOUND && v->state <= sarloc_VICTIM_RECOVERED && v->found_at == 0) {
    check_fail(r, "found_at", "0 while state is %u (found or later)", v->state);
  }
}

void check_team_status(const void* sample, CheckReport* r) {
  const sarloc_TeamStatus* t = sample;
  snprintf(r->sample, sizeof r->sample, "team '%.64s'", t->team_id);
  check_id(r, "team_id", t->team_id, sizeof t->team_id);
  check_stamp(r, "stamp", t->stamp);
  if (t->members._length > sarloc_TEAM_MEMBERS_MAX) {
    check_fail(r, "members", "%u entries: at most %u", t->members._length, sarloc_TEAM_MEMBERS_MAX);
    return;
  }
  char field[64];
  for (uint32_t i = 0; i < t->members._length; ++i) {
    const struct sarloc_MemberStatus* m = &t->members._buffer[i];
    snprintf(field, sizeof field, "members[%u].responder_id", i);
    check_id(r, field, m->responder_id, sizeof m->responder_id);
    snprintf(field, sizeof field, "members[%u].last_position", i);
    check_position(r, field, &m->last_position);
    snprintf(field, sizeof field, "members[%u].last_seen", i);
    check_stamp_or_zero(r, field, m->last_seen);
    snprintf(field, sizeof field, "members[%u].link", i);
    check_enum(r, field, m->link, sarloc_LINK_LOST);
    snprintf(field, sizeof field, "members[%u].accountability", i);
    check_enum(r, field, m->accountability, sarloc_ACCOUNTABILITY_MISSING);
  }
}

void check_incident_summary(const void* sample, CheckReport* r) {
  const sarloc_IncidentSummary* s = sample;
  snprintf(r->sample, sizeof r->sample, "incident '%.64s'", s->incident_id);
  check_id(r, "incident_id", s->incident_id, sizeof s->incident_id);
  check_stamp(r, "stamp", s->stamp);
  if (s->victims_located > s->victims_total) {
    check_fail(r, "victims_located", "%u: more than victims_total %u", s->victims_located, s->victims_total);
  }
  if (s->victims_found > s->victims_total) {
    check_fail(r, "victims_found", "%u: more than victims_total %u", s->victims_found, s->victims_total);
  }
  if (s->responders_link_lost > s->responders_total) {
    check_fail(r, "responders_link_lost", "%u: more than responders_total %u", s->responders_link_lost,
               s->responders_total);
  }
}

void check_node_status(const void* sample, CheckReport* r) {
  const sarloc_NodeStatus* s = sample;
  snprintf(r->sample, sizeof r->sample, "node '%.64s'", s->node_id);
  check_id(r, "node_id", s->node_id, sizeof s->node_id);
  check_enum(r, "kind", s->kind, sarloc_NODE_RECORDER);
  check_stamp(r, "stamp", s->stamp);
  if (s->rejects._length > sarloc_REJECT_REASONS_MAX) {
    check_fail(r, "rejects", "%u entries: at most %u", s->rejects._length, sarloc_REJECT_REASONS_MAX);
  } else {
    char field[64];
    for (uint32_t i = 0; i < s->rejects._length; ++i) {
      snprintf(field, sizeof field, "rejects[%u].reason", i);
      check_id(r, field, s->rejects._buffer[i].reason, sizeof s->rejects._buffer[i].reason);
    }
  }
  check_range(r, "cpu_percent", s->cpu_percent, 0.0, 100.0 * 1024); /* % of one core */
  check_range(r, "rss_mb", s->rss_mb, 0.0, 1e6);
}
