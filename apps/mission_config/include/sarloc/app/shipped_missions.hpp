#pragma once
// The missions sarloc ships: /usr/share/sarloc/missions of an installed sarloc-tools (found
// from the executable's own path, dds/install_layout.hpp), else the source tree's
// config/missions. The tools' default mission comes from here.
#include <string>

namespace sarloc::app {

/// The shipped mission file `name` ("default.yaml").
std::string shipped_mission(const std::string& name);

/// Where shipped_mission looks, for --help ("config/missions of the source tree, or
/// /usr/share/sarloc/missions when installed").
inline constexpr const char* kShippedMissionsHelp =
    "config/missions/ of the source tree; /usr/share/sarloc/missions/ once installed";

}  // namespace sarloc::app
