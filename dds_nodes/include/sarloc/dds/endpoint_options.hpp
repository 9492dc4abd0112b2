#pragma once
#include <functional>
#include <string>
#include <vector>

namespace sarloc::dds {

/// What a writer or reader may change on top of its topic's XML profile.
struct EndpointOptions {
  /// DDS partitions of the endpoint's publisher/subscriber (empty = the default partition).
  /// Sectors of one incident use them to split rescuers between core daemons.
  std::vector<std::string> partitions;
  /// A profile name to use instead of the topic's own ("<topic>.writer" / "<topic>.reader").
  std::string profile_override;
  /// Readers of FieldMeasurement and Odometry only: a sample enters the reader only if this
  /// says yes to its rescuer_id, decided by DDS before the reader's history
  /// (responder_filter.hpp). Unset: every sample enters.
  std::function<bool(const std::string& responder_id)> admit_responder;

  /// Options that only place the endpoint in `names` (a sector's partitions).
  static EndpointOptions in(const std::vector<std::string>& names) {
    EndpointOptions options;
    options.partitions = names;
    return options;
  }
};


}  // namespace sarloc::dds
