#include "sarloc/dds/security_check.hpp"

#include <filesystem>

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

}  // namespace

bool check_security(const eprosima::fastdds::dds::DomainParticipantQos& qos, const std::string& profile,
                    bool require_security) {
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
