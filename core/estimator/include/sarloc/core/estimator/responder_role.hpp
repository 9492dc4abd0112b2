#pragma once
// A responder's role in the mission chooses the estimator the daemon (and the device) runs for
// it: an avalanche rescuer's beacon search today, a firefighter's map-aided indoor
// localization. Names are the mission file's (`rescuers[].role`).
#include <cstdint>
#include <string>

namespace sarloc::estimator {

enum class ResponderRole : std::uint8_t {
  kAvalancheRescuer = 0,  ///< 3-axis avalanche-beacon receiver + odometry (SOG filter)
  kFirefighter = 1,       ///< boot INS odometry in a building (map-aided particle filter, seed 004)
};

/// "avalanche_rescuer", "firefighter".
const char* to_string(ResponderRole role);
/// Throws ConfigError "<key> = '<text>': must be one of avalanche_rescuer, firefighter".
ResponderRole parse_responder_role(const std::string& text, const std::string& key);

}  // namespace sarloc::estimator
