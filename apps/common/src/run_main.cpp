#include "sarloc/app/run_main.hpp"

#include <spdlog/spdlog.h>

#include <iostream>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::app {

int run_main(const std::string& program, const std::function<ExitCode()>& body) {
  try {
    return to_int(body());
  } catch (const ConfigError& e) {
    // Logging may not be set up yet when the config is what failed: stderr directly.
    std::cerr << program << ": configuration error: " << e.what() << "\n";
    return to_int(ExitCode::kConfig);
  } catch (const std::exception& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return to_int(ExitCode::kRuntime);
  }
}

}  // namespace sarloc::app
