#include "sarloc/dds/install_layout.hpp"

#include <system_error>

namespace sarloc::dds {

std::optional<std::filesystem::path> installed_root() {
  std::error_code error;
  const auto exe = std::filesystem::canonical("/proc/self/exe", error);
  if (error) return std::nullopt;
  const auto bin = exe.parent_path();
  if (bin.filename() != "bin" || bin.parent_path().filename() != "usr") return std::nullopt;
  return bin.parent_path().parent_path();
}

std::string dds_config_dir() {
  if (const auto root = installed_root()) return (*root / "etc/sarloc/dds").string();
  return SARLOC_DDS_CONFIG_DIR;
}

}  // namespace sarloc::dds
