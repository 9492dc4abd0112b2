#pragma once
// Fast DDS security fails OPEN: a misspelled dds.sec.auth.plugin value leaves the participant
// running unsecured with only an info log (NOTES, tested on 2.9.1). So a node checks its own
// security settings before it creates its participant, and refuses to start when they are
// incomplete, misspelled or point at missing files.
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include <optional>
#include <string>

namespace sarloc::dds {

/// Throws ConfigError naming the property and value when:
///  - `require_security` and the profile sets no dds.sec.* property;
///  - the profile sets no dds.sec.* property, can reach beyond this machine (network_reach)
///    and `allow_unauthenticated` is false: unsecured is the default on loopback only;
///  - any dds.sec.* property is set but authentication (builtin.PKI-DH), access control
///    (builtin.Access-Permissions) and encryption (builtin.AES-GCM-GMAC) are not all there,
///    spelled exactly;
///  - a "file:" value is not a file:// URI (Fast DDS's only accepted form) or names a file that
///    does not exist.
/// Returns true when the participant will be secured.
bool check_security(const eprosima::fastdds::dds::DomainParticipantQos& qos, const std::string& profile,
                    bool require_security, bool allow_unauthenticated);

/// Why a participant of this QoS can exchange packets with other machines (builtin transports,
/// a socket transport without an interface whitelist or with a non-loopback interface), or
/// nothing when every transport is shared memory or loopback-only.
std::optional<std::string> network_reach(const eprosima::fastdds::dds::DomainParticipantQos& qos);

}  // namespace sarloc::dds
