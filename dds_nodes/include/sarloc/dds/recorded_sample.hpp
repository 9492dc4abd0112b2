#pragma once
// A recorded DDS sample read back: one decoding for every reader of recordings (the report,
// the dashboard's replay), the same as a live reader's. The topic's generated type from its
// CDR bytes, then dds::to_core, which refuses what the core cannot mean.
//
//   if (const auto sample = dds::decode_recorded(topic, message.data))
//     std::visit([&](const auto& s) { on(s); }, *sample);
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "sarloc/dds/conversions.hpp"
#include "sarloc/idl/status.h"

namespace sarloc::dds {

/// What a recording's sample is once read. NodeStatus and VictimRecovery have no core form:
/// they are their generated types.
using RecordedSample =
    std::variant<avalanche::FieldMeasurement, responder::Odometry, responder::VictimEstimate, responder::Guidance,
                 responder::ResponderAlarm, responder::ResponderPosition, responder::ResponderCandidates,
                 incident::FusedVictim, incident::TeamStatus, incident::IncidentAlarm, incident::IncidentFrame,
                 incident::SearchPlanPicture, ::sarloc::NodeStatus, ::sarloc::VictimRecovery>;

/// The sample `bytes` holds on `topic` (a recording's channel name, "sarloc/..."). nullopt for
/// a topic not listed in RecordedSample (the recorder's JSON channels, the summary). Throws
/// InputError naming the topic when the bytes do not decode or hold what the core refuses.
std::optional<RecordedSample> decode_recorded(const std::string& topic, const std::vector<std::uint8_t>& bytes);

}  // namespace sarloc::dds
