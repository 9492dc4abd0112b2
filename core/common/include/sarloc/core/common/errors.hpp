#pragma once
// The small exception hierarchy for public preconditions (STYLE: three tiers of checks).
// Messages name the field, the value and the rule: "sog.initial_components = 0: must be > 0".
#include <stdexcept>
#include <string>

namespace sarloc {

/// Base of every error sarloc throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A configuration value breaks a rule (thrown by XxxConfig::validate() and config loaders).
class ConfigError : public Error {
 public:
  using Error::Error;
};

/// An input sample is unusable (NaN, absurd magnitude, out-of-order stamp, unknown id...).
class InputError : public Error {
 public:
  using Error::Error;
};

}  // namespace sarloc
