#pragma once
// What a config's validate() says: its ConfigError's message, "" when the config is valid.
// Config tests compare it whole ("key = value: rule"), so a check that stops throwing fails too.
#include <string>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::test {

template <typename Config>
std::string validation_error(const Config& config) {
  try {
    config.validate();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace sarloc::test
