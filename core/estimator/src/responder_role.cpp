#include "sarloc/core/estimator/responder_role.hpp"

#include "sarloc/core/common/errors.hpp"

namespace sarloc::estimator {

const char* to_string(ResponderRole role) {
  switch (role) {
    case ResponderRole::kAvalancheRescuer: return "avalanche_rescuer";
    case ResponderRole::kFirefighter: return "firefighter";
  }
  return "unknown";
}

ResponderRole parse_responder_role(const std::string& text, const std::string& key) {
  if (text == to_string(ResponderRole::kAvalancheRescuer)) return ResponderRole::kAvalancheRescuer;
  if (text == to_string(ResponderRole::kFirefighter)) return ResponderRole::kFirefighter;
  throw ConfigError(key + " = '" + text + "': must be one of avalanche_rescuer, firefighter");
}

}  // namespace sarloc::estimator
