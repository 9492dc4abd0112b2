#include "sarloc/dds/security_check.hpp"

#include <fastdds/rtps/transport/SocketTransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>

#include <filesystem>
#include <memory>
#include <optional>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::dds {
namespace {

struct Plugin {
  const char* property;
  const char* value;
  const char* what;
};

constexpr Plugin kPlugins[] = {
    {"dds.sec.auth.plugin", "builtin.PKI-DH", "authentication"},
    {"dds.sec.access.plugin", "builtin.Access-Permissions", "access control"},
    {"dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC", "encryption"},
};

bool is_loopback(const std::string& address) {
  return address.rfind("127.", 0) == 0 || address == "::1" || address == "lo" || address == "localhost";
}

}  // namespace

std::optional<std::string> network_reach(const eprosima::fastdds::dds::DomainParticipantQos& qos) {
  namespace rtps = eprosima::fastdds::rtps;
  if (qos.transport().use_builtin_transports) return std::string("its builtin transports use every interface");
  for (const auto& transport : qos.transport().user_transports) {
    if (std::dynamic_pointer_cast<rtps::SharedMemTransportDescriptor>(transport)) continue;
    const auto socket = std::dynamic_pointer_cast<rtps::SocketTransportDescriptor>(transport);
    if (!socket) return std::string("it has a transport that is neither shared memory nor a socket");
    if (socket->interfaceWhiteList.empty()) return std::string("a socket transport has no interface whitelist");
    for (const auto& address : socket->interfaceWhiteList) {
      if (!is_loopback(address)) return "a socket transport allows interface " + address;
    }
  }
  return std::nullopt;
}

bool check_security(const eprosima::fastdds::dds::DomainParticipantQos& qos, const std::string& profile,
                    bool require_security, bool allow_unauthenticated) {
  bool any = false;
  for (const auto& p : qos.properties().properties()) {
    if (p.name().rfind("dds.sec.", 0) != 0) continue;
    any = true;
    const std::string& value = p.value();
    // Fast DDS reads certificates, keys and signed documents only from "file://<path>" URIs
    // (an absolute path gives "file:///..."); "file:<path>" makes it refuse the participant.
    if (value.rfind("file:", 0) == 0) {
      if (value.rfind("file://", 0) != 0) {
        throw ConfigError("profile '" + profile + "': " + p.name() + " = '" + value +
                          "': a file must be given as file://<path>");
      }
      const std::string path = value.substr(7);
      if (!std::filesystem::is_regular_file(path)) {
        throw ConfigError("profile '" + profile + "': " + p.name() + " = '" + value + "': no such file");
      }
    }
  }
  if (!any) {
    if (require_security) {
      throw ConfigError("dds.require_security = true but profile '" + profile +
                        "' sets no dds.sec.* property: refusing to run unsecured");
    }
    // Unsecured is the default only where no packet leaves this machine.
    if (const auto reach = network_reach(qos); reach && !allow_unauthenticated) {
      throw ConfigError("dds.profile = '" + profile + "' reaches beyond this machine (" + *reach +
                        ") without DDS Security: anyone on that network could write the incident picture. Use the "
                        "node's secure.xml from deploy/security/make-certs.sh (dds.profiles_file, dds.profile: "
                        "sarloc_secure), or, for a drill on a closed network, dds.allow_unauthenticated: true");
    }
    return false;
  }
  for (const auto& plugin : kPlugins) {
    std::string value = "(not set)";
    for (const auto& p : qos.properties().properties()) {
      if (p.name() == plugin.property) value = p.value();
    }
    if (value != plugin.value) {
      throw ConfigError("profile '" + profile + "': " + plugin.property + " = '" + value + "': " + plugin.what +
                        " must be '" + plugin.value + "' (Fast DDS would run UNSECURED): refusing to start");
    }
  }
  return true;
}

}  // namespace sarloc::dds
