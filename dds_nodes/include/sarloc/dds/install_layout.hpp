#pragma once
// Where the shipped configuration is, for an installed sarloc and for a build tree alike.
// The Debian packages put executables in <root>/usr/bin and configuration in <root>/etc/sarloc
// (root "/" once installed; any folder a package was unpacked into with dpkg-deb -x), so an
// executable finds its defaults from its own path. One in a build tree (build/bin) uses the
// source tree's config/ (SARLOC_DDS_CONFIG_DIR).
#include <filesystem>
#include <optional>
#include <string>

namespace sarloc::dds {

/// <root> when this executable is an installed one (<root>/usr/bin/NAME), else nullopt.
std::optional<std::filesystem::path> installed_root();

/// The folder of the shipped Fast DDS profiles: <root>/etc/sarloc/dds when installed, else
/// the source tree's config/dds.
std::string dds_config_dir();

}  // namespace sarloc::dds
