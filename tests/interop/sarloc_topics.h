#ifndef SARLOC_INTEROP_SARLOC_TOPICS_H
#define SARLOC_INTEROP_SARLOC_TOPICS_H
/* Every sarloc topic as a Cyclone DDS application sees it: the topic name and type (the C type
 * idlc generated from the IDL files in idl/; its registered name, e.g. "sarloc::Guidance", is
 * the one Fast DDS uses), the QoS that matches config/dds/topics.xml, and the value checks of
 * its samples.
 * Keep in step with dds_nodes/include/sarloc/dds/topics.hpp and docs/topics.md. */
#include <dds/dds.h>
#include <stdbool.h>

#include "value_checks.h"

typedef void (*SampleCheck)(const void* sample, CheckReport* report);

typedef struct SarlocTopic {
  const char* name;                         /* "sarloc/guidance" */
  const dds_topic_descriptor_t* descriptor; /* idlc's sarloc_Guidance_desc */
  bool transient_local;                     /* else VOLATILE */
  int32_t depth;                            /* KEEP_LAST depth of topics.xml */
  dds_duration_t liveliness_lease;          /* AUTOMATIC lease, DDS_INFINITY when none */
  bool exclusive;                           /* OWNERSHIP EXCLUSIVE: the incident picture */
  SampleCheck check;
} SarlocTopic;

enum { kSarlocTopicCount = 10 };
extern const SarlocTopic kSarlocTopics[kSarlocTopicCount];

const SarlocTopic* find_sarloc_topic(const char* name);

/* QoS of a reader or writer that matches the Fast DDS endpoints of topics.xml (the same for
 * both kinds). Free with dds_delete_qos. */
dds_qos_t* sarloc_endpoint_qos(const SarlocTopic* topic);

/* Name of a dds_qos_policy_id_t that can make two endpoints incompatible. */
const char* sarloc_policy_name(uint32_t id);

#endif
