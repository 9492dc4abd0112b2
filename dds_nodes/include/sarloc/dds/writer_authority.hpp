#pragma once
// Who may write a sample about a responder, proven by DDS Security.
//
// DDS Security grants topics, not instances: every device identity may publish responder_position
// and responder_alarm, so without this a stolen device could raise a mayday "for r1" or move r1
// on the map. The builtin PKI-DH authentication ties bytes 0-5 of a participant's GUID prefix to
// SHA-256 of its certificate's subject (Fast DDS 2.9, PKIDH.cpp: the prefix is derived so, and a
// handshake whose GUID does not match is refused), and every writer's GUID starts with its
// participant's prefix. So a reader can tell which identity wrote a sample
// (SampleInfo::publication_handle) without ever seeing the writer's certificate: it recomputes
// the prefix of the identity that should have.
//
// sarloc identities are those deploy/security/make-certs.sh issues: subject O=sarloc, CN=<node>,
// where a device's node is its responder id and a core daemon's its node id.
#include <fastdds/rtps/common/InstanceHandle.h>

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

namespace sarloc::dds {

class Participant;

/// The 47 bits (and the flag bit) of a GUID prefix that PKI-DH derives from the subject
/// O=sarloc, CN=`node_id`.
using IdentityPrefix = std::array<std::uint8_t, 6>;
IdentityPrefix identity_prefix_of(const std::string& node_id);

/// True when the participant's own GUID proves the identity `node_id`: a node that speaks for
/// responders checks its certificate at start, since the others judge it by that name.
bool proves_identity(const Participant& participant, const std::string& node_id);

/// Throws ConfigError when `participant` runs DDS Security with a certificate that is not
/// O=sarloc, CN=`node_id`: the other nodes would refuse everything it writes about responders.
void require_identity(const Participant& participant, const std::string& node_id, const std::string& key);

class WriterAuthority {
 public:
  /// Who may write about a responder besides the responder's own device.
  enum class Speakers {
    kDevice,         ///< only its device: alarms, device positions, sensor samples
    kDeviceOrCore,   ///< its device or a core daemon: estimates, map-aided positions
  };

  /// The core daemons are `participant.config().core_node_ids`.
  explicit WriterAuthority(std::shared_ptr<const Participant> participant);

  /// Without DDS Security nothing proves who wrote a sample: every writer is admitted (the
  /// dashboard's header says so in red). With it: this participant's own writers, the
  /// identity CN=`responder_id`, and for kDeviceOrCore the mission's core daemons.
  bool admits(const eprosima::fastrtps::rtps::InstanceHandle_t& writer, const std::string& responder_id,
              Speakers speakers) const;

  /// "r2" or "core-west" when the writer's prefix is one of the identities seen so far,
  /// otherwise its participant's 24 hex digits: for the refusal's log line.
  std::string writer_name(const eprosima::fastrtps::rtps::InstanceHandle_t& writer) const;
  /// The log line of a refusal: "<what> about 'r1' written by <writer_name>, which may not
  /// speak for it (DDS Security identity)".
  std::string refusal(const std::string& what, const eprosima::fastrtps::rtps::InstanceHandle_t& writer,
                      const std::string& responder_id) const;

 private:
  IdentityPrefix prefix_of(const std::string& node_id) const;

  std::shared_ptr<const Participant> participant_;
  bool secured_ = false;
  std::vector<std::pair<std::string, IdentityPrefix>> cores_;
  mutable std::mutex mutex_;
  mutable std::unordered_map<std::string, IdentityPrefix> devices_;  // a cache, cleared when large
};

}  // namespace sarloc::dds
