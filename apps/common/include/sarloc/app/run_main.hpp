#pragma once
// The one place that maps sarloc's typed exceptions to exit codes (docs/operations.md):
//   ConfigError -> kConfig (3), any other sarloc::Error or std::exception -> kRuntime (4).
//
//   int main(int argc, char** argv) {
//     return sarloc::app::run_main("sarloc-core", [&] { ...; return ExitCode::kOk; });
//   }
#include <functional>
#include <string>

#include "sarloc/app/exit_codes.hpp"

namespace sarloc::app {

int run_main(const std::string& program, const std::function<ExitCode()>& body);

}  // namespace sarloc::app
