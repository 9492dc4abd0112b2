#include "sarloc/app/shipped_missions.hpp"

#include "sarloc/dds/install_layout.hpp"

namespace sarloc::app {

std::string shipped_mission(const std::string& name) {
  if (const auto root = dds::installed_root()) return (*root / "usr/share/sarloc/missions" / name).string();
  return std::string(SARLOC_SOURCE_DIR) + "/config/missions/" + name;
}

}  // namespace sarloc::app
