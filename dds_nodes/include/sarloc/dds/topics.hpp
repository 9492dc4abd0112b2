#pragma once
// Every sarloc topic: its IDL type, its name on the wire and its QoS profile in
// config/dds/topics.xml ("<profile>.writer" / "<profile>.reader"). docs/topics.md is the
// human-readable version of this table.
#include "sarloc/dds/key_hashed_type.hpp"
#include "sarloc/idl/avalanchePubSubTypes.h"
#include "sarloc/idl/commonPubSubTypes.h"
#include "sarloc/idl/handoverPubSubTypes.h"
#include "sarloc/idl/incidentPubSubTypes.h"
#include "sarloc/idl/responderPubSubTypes.h"
#include "sarloc/idl/statusPubSubTypes.h"

namespace sarloc::dds {

template <class T>
struct TopicTraits;  // undefined for types that are not topics: a compile error, on purpose

#define SARLOC_DDS_TOPIC(Type, profile_name)                                      \
  template <>                                                                     \
  struct TopicTraits<::sarloc::Type> {                                            \
    using PubSubType = KeyHashedType<::sarloc::Type##PubSubType, ::sarloc::Type>; \
    static constexpr const char* kName = "sarloc/" profile_name;                  \
    static constexpr const char* kProfile = profile_name;                         \
  }

SARLOC_DDS_TOPIC(FieldMeasurement, "field_measurement");
SARLOC_DDS_TOPIC(Odometry, "odometry");
SARLOC_DDS_TOPIC(VictimEstimate, "victim_estimate");
SARLOC_DDS_TOPIC(Guidance, "guidance");
SARLOC_DDS_TOPIC(ResponderPosition, "responder_position");
SARLOC_DDS_TOPIC(ResponderCandidates, "responder_candidates");
SARLOC_DDS_TOPIC(IncidentFrame, "incident_frame");
SARLOC_DDS_TOPIC(FusedVictim, "fused_victim");
SARLOC_DDS_TOPIC(TeamStatus, "team_status");
SARLOC_DDS_TOPIC(IncidentSummary, "incident_summary");
SARLOC_DDS_TOPIC(SearchPlan, "search_plan");
SARLOC_DDS_TOPIC(ResponderAlarm, "responder_alarm");
SARLOC_DDS_TOPIC(IncidentAlarm, "incident_alarm");
SARLOC_DDS_TOPIC(AlarmAcknowledgement, "alarm_acknowledgement");
SARLOC_DDS_TOPIC(VictimRecovery, "victim_recovery");
SARLOC_DDS_TOPIC(DigOrder, "dig_order");
SARLOC_DDS_TOPIC(DepositDrawing, "deposit_drawing");
SARLOC_DDS_TOPIC(RescuerHandover, "rescuer_handover");
SARLOC_DDS_TOPIC(NodeStatus, "node_status");

#undef SARLOC_DDS_TOPIC

}  // namespace sarloc::dds
