#pragma once
// Tests that run an outside program (node, chromium) fail, never skip, when it is missing, and
// name the Debian package that brings it (scripts/install-deps installs them all).
//
//   ASSERT_TRUE(sarloc::test::has_program("node", "nodejs"));
#include <gtest/gtest.h>

#include <cstdio>
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

/// What a shell command printed, stdout and stderr together (empty when it could not start).
inline std::string output_of(const std::string& command) {
  std::string out;
  if (FILE* pipe = ::popen((command + " 2>&1").c_str(), "r")) {
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
    ::pclose(pipe);
  }
  return out;
}

/// node and Chromium, for the tests that read recordings with @mcap/core or drive a browser.
inline ::testing::AssertionResult has_node() { return has_program("node", "nodejs"); }
inline ::testing::AssertionResult has_chromium() { return has_program("/usr/bin/chromium", "chromium"); }

}  // namespace sarloc::test
