#define _POSIX_C_SOURCE 200809L
#include <dds/dds.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "avalanche.h"
#include "responder.h"
#include "dipole_field.h"
#include "interop_modes.h"
#include "sample_checks.h"
#include "sarloc_topics.h"
#include "status.h"

/* The scene, in the incident frame (ENU, m; snow surface at z = 0). The moment is victim A's of
 * config/missions/default.yaml (EN 300 718 range); the receiver is held 1 m above the snow. */
static const struct sarloc_Vector3 kTransmitter = {3.0, 18.0, -1.2};
static const struct sarloc_Vector3 kMoment = {0.012, -0.006, 0.004};
static const struct sarloc_Vector3 kStart = {0.0, 0.0, 1.0};
static const double kStartYaw = 1.5707963267948966; /* facing north */
static const double kStepM = 1.0;
static const int64_t kEpochNs = 1000000000LL; /* one epoch per second of stamps */
static const uint32_t kSignal = 1;
static const double kMaxFinalErrorM = 1.0;

static const double kDeg = 3.14159265358979323846 / 180.0;

typedef struct Pose {
  struct sarloc_Vector3 position; /* antenna, ENU */
  double yaw;                     /* of R in ENU; roll = pitch = 0 */
} Pose;

typedef struct Endpoints {
  dds_entity_t participant, measurement_writer, odometry_writer, estimate_reader, guidance_reader, status_reader;
} Endpoints;

static dds_entity_t make_endpoint(dds_entity_t participant, const char* topic_name, int is_writer) {
  const SarlocTopic* topic = find_sarloc_topic(topic_name);
  const dds_entity_t t = dds_create_topic(participant, topic->descriptor, topic->name, NULL, NULL);
  if (t < 0) return t;
  dds_qos_t* qos = sarloc_endpoint_qos(topic);
  const dds_entity_t e =
      is_writer ? dds_create_writer(participant, t, qos, NULL) : dds_create_reader(participant, t, qos, NULL);
  dds_delete_qos(qos);
  if (e < 0) fprintf(stderr, "%s: cannot create the endpoint: %s\n", topic_name, dds_strretcode(e));
  return e;
}

static int create_endpoints(uint32_t domain, Endpoints* ep) {
  ep->participant = dds_create_participant(domain, NULL, NULL);
  if (ep->participant < 0) {
    fprintf(stderr, "cannot create a participant on domain %u: %s\n", domain, dds_strretcode(ep->participant));
    return 0;
  }
  ep->measurement_writer = make_endpoint(ep->participant, "sarloc/field_measurement", 1);
  ep->odometry_writer = make_endpoint(ep->participant, "sarloc/odometry", 1);
  ep->estimate_reader = make_endpoint(ep->participant, "sarloc/victim_estimate", 0);
  ep->guidance_reader = make_endpoint(ep->participant, "sarloc/guidance", 0);
  ep->status_reader = make_endpoint(ep->participant, "sarloc/node_status", 0);
  return ep->measurement_writer > 0 && ep->odometry_writer > 0 && ep->estimate_reader > 0 && ep->guidance_reader > 0 &&
         ep->status_reader > 0;
}

/* The daemon's readers and writers are discovered (both directions of the match). */
static int wait_for_daemon(const Endpoints* ep, double timeout_s) {
  const dds_time_t end = dds_time() + (dds_duration_t)(timeout_s * 1e9);
  while (!interop_stop_requested && dds_time() < end) {
    dds_publication_matched_status_t m = {0}, o = {0};
    dds_subscription_matched_status_t e = {0}, g = {0};
    dds_get_publication_matched_status(ep->measurement_writer, &m);
    dds_get_publication_matched_status(ep->odometry_writer, &o);
    dds_get_subscription_matched_status(ep->estimate_reader, &e);
    dds_get_subscription_matched_status(ep->guidance_reader, &g);
    if (m.current_count > 0 && o.current_count > 0 && e.current_count > 0 && g.current_count > 0) return 1;
    dds_sleepfor(DDS_MSECS(50));
  }
  return 0;
}

/* Why a match failed, when QoS is the reason. */
static void report_incompatible(const Endpoints* ep) {
  const dds_entity_t writers[2] = {ep->measurement_writer, ep->odometry_writer};
  const dds_entity_t readers[2] = {ep->estimate_reader, ep->guidance_reader};
  const char* writer_topics[2] = {"sarloc/field_measurement", "sarloc/odometry"};
  const char* reader_topics[2] = {"sarloc/victim_estimate", "sarloc/guidance"};
  for (int i = 0; i < 2; ++i) {
    dds_offered_incompatible_qos_status_t w = {0};
    dds_requested_incompatible_qos_status_t r = {0};
    dds_get_offered_incompatible_qos_status(writers[i], &w);
    dds_get_requested_incompatible_qos_status(readers[i], &r);
    if (w.total_count > 0) {
      fprintf(stderr, "  %s writer: incompatible %s\n", writer_topics[i], sarloc_policy_name(w.last_policy_id));
    }
    if (r.total_count > 0) {
      fprintf(stderr, "  %s reader: incompatible %s\n", reader_topics[i], sarloc_policy_name(r.last_policy_id));
    }
  }
}

static void diagonal(double* m, int n, const double* variances) {
  memset(m, 0, sizeof(double) * (size_t)(n * n));
  for (int i = 0; i < n; ++i) m[i * n + i] = variances[i];
}

/* The values published are exact; the noise the device states is that of sarloc's simulated
 * sensors (docs/estimation/avalanche.md): 5 % of |H| plus a floor per field axis, attitude
 * 1 deg roll/pitch and 5 deg yaw; odometry 3 % of the step, 0.5 deg roll/pitch, 1 deg yaw. */
static sarloc_FieldMeasurement measurement_at(const char* rescuer_id, uint64_t sequence, int64_t stamp,
                                              const Pose* pose) {
  sarloc_FieldMeasurement m;
  memset(&m, 0, sizeof m);
  snprintf(m.rescuer_id, sizeof m.rescuer_id, "%s", rescuer_id);
  m.signal_id = kSignal;
  m.sequence_number = sequence;
  m.stamp = stamp;
  const struct sarloc_Vector3 r = {pose->position.x - kTransmitter.x, pose->position.y - kTransmitter.y,
                                   pose->position.z - kTransmitter.z};
  const struct sarloc_Vector3 h_enu = dipole_field(&r, &kMoment);
  const struct sarloc_Vector3 rpy = {0.0, 0.0, pose->yaw};
  m.field = to_frame(&rpy, &h_enu);
  const double sigma = 0.05 * vector3_norm(&h_enu) + 2.1e-9;
  m.noise_stddev.x = m.noise_stddev.y = m.noise_stddev.z = sigma;
  m.valid_axes = sarloc_FIELD_AXIS_X | sarloc_FIELD_AXIS_Y | sarloc_FIELD_AXIS_Z;
  m.signal_event = sequence == 1 ? sarloc_SIGNAL_NEW : sarloc_SIGNAL_TRACKED;
  m.has_orientation = true;
  m.orientation_rpy = rpy;
  const double attitude[3] = {pow(1.0 * kDeg, 2), pow(1.0 * kDeg, 2), pow(5.0 * kDeg, 2)};
  diagonal(m.orientation_covariance, 3, attitude);
  return m;
}

/* Walks one step after turning by `turn`, and returns the odometry of that step: translation
 * in the body frame at the step's start, rotation rpy of the end frame in the start frame. */
static sarloc_Odometry step(const char* rescuer_id, uint64_t sequence, int64_t start, int64_t end, Pose* pose,
                            double turn) {
  const struct sarloc_Vector3 rpy_before = {0.0, 0.0, pose->yaw};
  pose->yaw = wrap_angle(pose->yaw + turn);
  const struct sarloc_Vector3 delta = {kStepM * cos(pose->yaw), kStepM * sin(pose->yaw), 0.0};
  pose->position.x += delta.x;
  pose->position.y += delta.y;
  sarloc_Odometry o;
  memset(&o, 0, sizeof o);
  snprintf(o.rescuer_id, sizeof o.rescuer_id, "%s", rescuer_id);
  o.sequence_number = sequence;
  o.interval_start = start;
  o.interval_end = end;
  o.translation = to_frame(&rpy_before, &delta);
  o.rotation_rpy.z = wrap_angle(turn);
  const double s_t = fmax(0.03 * kStepM, 0.01);
  const double noise[6] = {s_t * s_t, s_t * s_t, s_t * s_t, pow(0.5 * kDeg, 2), pow(0.5 * kDeg, 2), pow(1.0 * kDeg, 2)};
  diagonal(o.covariance, 6, noise);
  o.source = sarloc_ODOMETRY_OTHER;
  return o;
}

/* Where the transmitter is in the rescuer frame G (ENU axes, centred on the antenna). */
static struct sarloc_Vector3 transmitter_in_g(const Pose* pose) {
  const struct sarloc_Vector3 g = {kTransmitter.x - pose->position.x, kTransmitter.y - pose->position.y,
                                   kTransmitter.z - pose->position.z};
  return g;
}

typedef struct Answer {
  int have_estimate, have_guidance;
  sarloc_VictimEstimate estimate; /* top_components not kept (loaned memory) */
  sarloc_Guidance guidance;
} Answer;

/* Takes what arrived; keeps this rescuer's answers to `sequence` (values checked). Returns the
 * number of samples with bad values. */
static int take_answers(const Endpoints* ep, const char* rescuer_id, uint64_t sequence, Answer* answer) {
  int bad = 0;
  void* samples[16] = {NULL};
  dds_sample_info_t infos[16];
  const dds_entity_t readers[2] = {ep->estimate_reader, ep->guidance_reader};
  for (int k = 0; k < 2; ++k) {
    const int n = dds_take(readers[k], samples, infos, 16, 16);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      CheckReport report = check_begin(k == 0 ? "sarloc/victim_estimate" : "sarloc/guidance");
      if (k == 0) {
        const sarloc_VictimEstimate* e = samples[i];
        check_victim_estimate(e, &report);
        if (strcmp(e->rescuer_id, rescuer_id) == 0 && e->measurement_sequence == sequence) {
          answer->have_estimate = 1;
          answer->estimate = *e;
          memset(&answer->estimate.top_components, 0, sizeof answer->estimate.top_components);
        }
      } else {
        const sarloc_Guidance* g = samples[i];
        check_guidance(g, &report);
        if (strcmp(g->rescuer_id, rescuer_id) == 0 && g->measurement_sequence == sequence) {
          answer->have_guidance = 1;
          answer->guidance = *g;
        }
      }
      bad += report.failures > 0;
    }
    if (n > 0) dds_return_loan(readers[k], samples, n);
  }
  return bad;
}

static const char* mode_name(sarloc_GuidanceMode mode) {
  static const char* names[] = {"OPENING", "APPROACH", "FINE_SEARCH", "FOUND"};
  return mode <= sarloc_GUIDANCE_FOUND ? names[mode] : "?";
}

/* The daemon's NodeStatus counts what it accepted and refused: every sample sent must be
 * accepted. It is published once a second. */
static int check_daemon_accepted(const Endpoints* ep, uint64_t sent, double timeout_s) {
  const dds_time_t end = dds_time() + (dds_duration_t)(timeout_s * 1e9);
  uint64_t accepted = 0, rejected = 0;
  while (dds_time() < end && !interop_stop_requested) {
    void* samples[8] = {NULL};
    dds_sample_info_t infos[8];
    const int n = dds_take(ep->status_reader, samples, infos, 8, 8);
    for (int i = 0; i < n; ++i) {
      const sarloc_NodeStatus* s = samples[i];
      if (!infos[i].valid_data || s->kind != sarloc_NODE_CORE) continue;
      accepted = s->samples_accepted;
      rejected = s->samples_rejected;
      for (uint32_t k = 0; k < s->rejects._length; ++k) {
        printf("  daemon rejects: %s x %llu\n", s->rejects._buffer[k].reason,
               (unsigned long long)s->rejects._buffer[k].count);
      }
    }
    if (n > 0) dds_return_loan(ep->status_reader, samples, n);
    if (accepted >= sent || rejected > 0) break;
    dds_sleepfor(DDS_MSECS(100));
  }
  printf("daemon NodeStatus: %llu samples accepted, %llu rejected (sent %llu)\n", (unsigned long long)accepted,
         (unsigned long long)rejected, (unsigned long long)sent);
  return accepted >= sent && rejected == 0;
}

int run_publish(const InteropOptions* options) {
  Endpoints ep;
  if (!create_endpoints(options->domain, &ep)) {
    if (ep.participant > 0) dds_delete(ep.participant);
    return kExitCannotRun;
  }
  int failed = 0;
  if (!wait_for_daemon(&ep, options->timeout_s)) {
    fprintf(stderr, "FAIL: no sarloc-core matched on domain %u within %.0f s\n", options->domain, options->timeout_s);
    report_incompatible(&ep);
    dds_delete(ep.participant);
    return kExitFailed;
  }
  printf("matched the core daemon; walking %d epochs as rescuer '%s'\n", options->epochs, options->rescuer_id);

  Pose pose = {kStart, kStartYaw};
  const int64_t t0 = wall_now_ns();
  uint64_t sent = 0;
  Answer answer;
  for (int k = 0; k < options->epochs && !failed && !interop_stop_requested; ++k) {
    const int64_t stamp = t0 + k * kEpochNs;
    if (k > 0) {
      /* A gentle weave, so odometry carries rotations as well as translations. */
      const sarloc_Odometry o = step(options->rescuer_id, (uint64_t)k, stamp - kEpochNs, stamp, &pose, 0.15 * sin(k));
      if (dds_write(ep.odometry_writer, &o) != DDS_RETCODE_OK) failed = 1;
      sent++;
    }
    const uint64_t sequence = (uint64_t)k + 1;
    const sarloc_FieldMeasurement m = measurement_at(options->rescuer_id, sequence, stamp, &pose);
    if (dds_write(ep.measurement_writer, &m) != DDS_RETCODE_OK) failed = 1;
    sent++;
    if (failed) {
      fprintf(stderr, "FAIL: dds_write refused epoch %d\n", k);
      break;
    }

    memset(&answer, 0, sizeof answer);
    const dds_time_t end = dds_time() + (dds_duration_t)(options->answer_timeout_s * 1e9);
    while (!(answer.have_estimate && answer.have_guidance) && dds_time() < end && !interop_stop_requested) {
      if (take_answers(&ep, options->rescuer_id, sequence, &answer) > 0) failed = 1;
      if (!(answer.have_estimate && answer.have_guidance)) dds_sleepfor(DDS_MSECS(5));
    }
    if (!answer.have_estimate || !answer.have_guidance) {
      fprintf(stderr, "FAIL: no %s for rescuer '%s' measurement_sequence %llu within %.1f s\n",
              answer.have_estimate ? "Guidance" : "VictimEstimate", options->rescuer_id, (unsigned long long)sequence,
              options->answer_timeout_s);
      failed = 1;
      break;
    }
    const struct sarloc_Vector3* est = &answer.estimate.relative.position;
    const struct sarloc_Vector3 truth = transmitter_in_g(&pose);
    printf(
        "epoch %2d seq %2llu: %-16s bearing %+6.1f deg, distance %5.1f m; estimate in G (%+6.2f %+6.2f %+6.2f), "
        "truth (%+6.2f %+6.2f %+6.2f), status %u\n",
        k, (unsigned long long)sequence, mode_name(answer.guidance.mode), answer.guidance.bearing_rad / kDeg,
        answer.guidance.distance_m, est->x, est->y, est->z, truth.x, truth.y, truth.z, answer.estimate.status);
  }
  if (!failed && !interop_stop_requested) {
    /* Exact fields along the walk: the daemon converges onto the transmitter (about 0.1 m off
     * after 16 epochs) only if it reads every field, frame and unit as docs/topics.md says. */
    const struct sarloc_Vector3* est = &answer.estimate.relative.position;
    const struct sarloc_Vector3 truth = transmitter_in_g(&pose);
    const struct sarloc_Vector3 off = {est->x - truth.x, est->y - truth.y, est->z - truth.z};
    const double error = vector3_norm(&off);
    printf("final estimate %.2f m from the transmitter\n", error);
    if (error > kMaxFinalErrorM) {
      fprintf(stderr, "FAIL: the daemon's last estimate is %.2f m off (at most %.1f m): a convention differs\n", error,
              kMaxFinalErrorM);
      failed = 1;
    }
  }
  if (!failed && !interop_stop_requested && !check_daemon_accepted(&ep, sent, 3.0)) {
    fprintf(stderr, "FAIL: the daemon did not accept every sample sent\n");
    failed = 1;
  }
  dds_delete(ep.participant);
  return failed || interop_stop_requested ? kExitFailed : kExitOk;
}
