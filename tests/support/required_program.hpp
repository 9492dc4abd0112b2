#pragma once
// Tests that run an outside program (node, chromium) fail, never skip, when it is missing, and
// name the Debian package that brings it (scripts/install-deps installs them all).
//
//   ASSERT_TRUE(sarloc::test::has_program("node", "nodejs"));
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

namespace sarloc::test {

/// Success when `program` is an executable on PATH (or an absolute path to one); otherwise a
/// failure naming it and `package`.
inline ::testing::AssertionResult has_program(const std::string& program, const std::string& package) {
  namespace fs = std::filesystem;
  auto executable = [](const fs::path& p) {
    std::error_code ec;
    const auto status = fs::status(p, ec);
    return !ec && fs::is_regular_file(status) && (status.permissions() & fs::perms::others_exec) != fs::perms::none;
  };
  if (program.find('/') != std::string::npos) {
    if (executable(program)) return ::testing::AssertionSuccess();
  } else if (const char* path = std::getenv("PATH")) {
    std::stringstream dirs(path);
    for (std::string dir; std::getline(dirs, dir, ':');) {
      if (!dir.empty() && executable(fs::path(dir) / program)) return ::testing::AssertionSuccess();
    }
  }
  return ::testing::AssertionFailure() << "program '" << program << "' not found: this test needs the Debian package "
                                       << package << " (scripts/install-deps installs it)";
}

/// node and Chromium, for the tests that read recordings with @mcap/core or drive a browser.
inline ::testing::AssertionResult has_node() { return has_program("node", "nodejs"); }
inline ::testing::AssertionResult has_chromium() { return has_program("/usr/bin/chromium", "chromium"); }

}  // namespace sarloc::test
