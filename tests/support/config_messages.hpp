#pragma once
// What a config's validate() says: its ConfigError's message, "" when the config is valid.
// Config tests compare it whole ("key = value: rule"), so a check that stops throwing fails too.
#include <string>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::test {

/// The ConfigError message `f` throws, "" when it throws none.
template <typename F>
std::string config_error_of(F f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

template <typename Config>
std::string validation_error(const Config& config) {
  return config_error_of([&] { config.validate(); });
}

}  // namespace sarloc::test
