#pragma once
// An orderly stop said on DDS before leaving (docs/operations.md, "Signing off"): a node
// disposes its own instance before its writer goes. A responder's device disposes its
// ResponderPosition instance, so that incident command records the responder as signed off
// (accounted for, no alarm) instead of lost; a core daemon or an incident-command instance its
// NodeStatus instance. A process that crashes or is killed says nothing and is reported lost
// within the lease.
#include <chrono>
#include <string>

#include "sarloc/dds/topics.hpp"
#include "sarloc/dds/writer.hpp"

namespace sarloc::dds {

/// Disposes `responder_id`'s position instance on the device's own writer and waits up to
/// `timeout` for every matched reader to acknowledge it. False when DDS refused the disposal
/// or a reader did not acknowledge in time (incident command may then report a lost link).
bool sign_off(Writer<::sarloc::ResponderPosition>& device_position_writer, const std::string& responder_id,
              std::chrono::milliseconds timeout);

/// The same for a core daemon or an incident-command instance: disposes its own NodeStatus
/// instance (key: node_id). Readers then know it stopped in order, not that it was lost.
bool sign_off(Writer<::sarloc::NodeStatus>& status_writer, const std::string& node_id, std::chrono::milliseconds timeout);

}  // namespace sarloc::dds
