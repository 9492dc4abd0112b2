#include "sarloc_topics.h"

#include <string.h>

#include "avalanche.h"
#include "responder.h"
#include "incident.h"
#include "sample_checks.h"
#include "status.h"

#define LEASE_3S DDS_SECS(3)

/* name, type, TRANSIENT_LOCAL, depth, liveliness lease, exclusive, checks: as
 * config/dds/topics.xml. The picture topics' writers offer MANUAL_BY_TOPIC with a 3 s lease: an
 * AUTOMATIC reader with no lease matches them. */
const SarlocTopic kSarlocTopics[kSarlocTopicCount] = {
    {"sarloc/field_measurement", &sarloc_FieldMeasurement_desc, false, 16, DDS_INFINITY, false, check_field_measurement},
    {"sarloc/odometry", &sarloc_Odometry_desc, false, 64, DDS_INFINITY, false, check_odometry},
    {"sarloc/victim_estimate", &sarloc_VictimEstimate_desc, true, 1, DDS_INFINITY, false, check_victim_estimate},
    {"sarloc/guidance", &sarloc_Guidance_desc, true, 1, DDS_INFINITY, false, check_guidance},
    {"sarloc/responder_position", &sarloc_ResponderPosition_desc, true, 1, LEASE_3S, false, check_responder_position},
    {"sarloc/incident_frame", &sarloc_IncidentFrame_desc, true, 1, DDS_INFINITY, true, check_incident_frame},
    {"sarloc/fused_victim", &sarloc_FusedVictim_desc, true, 1, DDS_INFINITY, true, check_fused_victim},
    {"sarloc/team_status", &sarloc_TeamStatus_desc, true, 1, DDS_INFINITY, true, check_team_status},
    {"sarloc/incident_summary", &sarloc_IncidentSummary_desc, true, 1, DDS_INFINITY, true, check_incident_summary},
    {"sarloc/node_status", &sarloc_NodeStatus_desc, true, 1, LEASE_3S, false, check_node_status},
};

const SarlocTopic* find_sarloc_topic(const char* name) {
  for (int i = 0; i < kSarlocTopicCount; ++i) {
    if (strcmp(kSarlocTopics[i].name, name) == 0) return &kSarlocTopics[i];
  }
  return NULL;
}

dds_qos_t* sarloc_endpoint_qos(const SarlocTopic* topic) {
  dds_qos_t* qos = dds_create_qos();
  /* Fast DDS readers default to BEST_EFFORT and Cyclone readers too: sarloc is RELIABLE. */
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  /* A TRANSIENT_LOCAL reader does not match a VOLATILE writer: follow the writer's kind. */
  dds_qset_durability(qos, topic->transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, topic->depth);
  /* A reader's lease must not be shorter than the writer's (3 s on two topics). */
  dds_qset_liveliness(qos, DDS_LIVELINESS_AUTOMATIC, topic->liveliness_lease);
  /* The picture is OWNERSHIP EXCLUSIVE (the active incident command's writer only): a SHARED
   * reader does not match an EXCLUSIVE writer. */
  dds_qset_ownership(qos, topic->exclusive ? DDS_OWNERSHIP_EXCLUSIVE : DDS_OWNERSHIP_SHARED);
  /* Fast DDS 2.9 writes and reads only XCDR1 (plain CDR); Cyclone allows XCDR1 for @final
   * types only (docs/topics.md, "Interoperability with other DDS vendors"). */
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(qos, 1, &xcdr1);
  return qos;
}

/* The policies that can make a reader and a writer incompatible. */
const char* sarloc_policy_name(uint32_t id) {
  switch (id) {
    case DDS_DURABILITY_QOS_POLICY_ID:
      return "DURABILITY";
    case DDS_PRESENTATION_QOS_POLICY_ID:
      return "PRESENTATION";
    case DDS_DEADLINE_QOS_POLICY_ID:
      return "DEADLINE";
    case DDS_LATENCYBUDGET_QOS_POLICY_ID:
      return "LATENCY_BUDGET";
    case DDS_OWNERSHIP_QOS_POLICY_ID:
      return "OWNERSHIP";
    case DDS_LIVELINESS_QOS_POLICY_ID:
      return "LIVELINESS";
    case DDS_RELIABILITY_QOS_POLICY_ID:
      return "RELIABILITY";
    case DDS_DESTINATIONORDER_QOS_POLICY_ID:
      return "DESTINATION_ORDER";
    case DDS_TYPE_CONSISTENCY_ENFORCEMENT_QOS_POLICY_ID:
      return "TYPE_CONSISTENCY";
    case DDS_DATA_REPRESENTATION_QOS_POLICY_ID:
      return "DATA_REPRESENTATION";
    default:
      return "another policy";
  }
}
