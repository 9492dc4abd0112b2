#pragma once
// An orderly stop said on DDS before leaving (docs/topics.md, "Signing off"): a responder's
// device disposes its own ResponderPosition instance, so that incident command records the
// responder as signed off (accounted for, no alarm) instead of lost when its writer goes.
// A device that crashes or is killed says nothing and is reported lost within the lease.
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

}  // namespace sarloc::dds
