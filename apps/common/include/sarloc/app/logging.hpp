#pragma once
// spdlog set-up shared by every executable: one format, a level from --log-level.
#include <string>

namespace sarloc::app {

/// Level names: trace, debug, info, warn, error, critical, off. Throws ConfigError otherwise.
/// `name` tags every line (several processes of one mission share a terminal).
void setup_logging(const std::string& level, const std::string& name = "sarloc");

}  // namespace sarloc::app
