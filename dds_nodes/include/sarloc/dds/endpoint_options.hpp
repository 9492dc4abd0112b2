#pragma once
#include <string>
#include <vector>

#include "sarloc/dds/responder_predicate.hpp"

namespace sarloc::dds {

/// What a writer or reader may change on top of its topic's XML profile.
struct EndpointOptions {
  /// DDS partitions of the endpoint's publisher/subscriber (empty = the default partition).
  /// Sectors of one incident use them to split rescuers between core daemons.
  std::vector<std::string> partitions;
  /// A profile name to use instead of the topic's own ("<topic>.writer" / "<topic>.reader").
  std::string profile_override;
  /// Readers of FieldMeasurement and Odometry only: a sample enters the reader only if this
  /// says yes to its rescuer_id (and first step), decided by DDS before the reader's history
  /// (responder_filter.hpp). Unset: every sample enters.
  ResponderPredicate admit_responder;

  /// Options that only place the endpoint in `names` (a sector's partitions).
  static EndpointOptions in(const std::vector<std::string>& names) {
    EndpointOptions options;
    options.partitions = names;
    return options;
  }
};

/// A responder device's own ResponderPosition writer (avalanche rescuer or firefighter), and
/// incident command's second reader of those: the `responder_position.device` profiles,
/// MANUAL_BY_TOPIC with a 3 s lease, so a killed device is reported lost 3 s after its last
/// assertion (config/dds/topics.xml has why).
inline EndpointOptions device_position_options(bool reader = false) {
  EndpointOptions options;
  options.profile_override = reader ? "responder_position.device.reader" : "responder_position.device.writer";
  return options;
}


}  // namespace sarloc::dds
