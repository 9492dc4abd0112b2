#pragma once
// The checks of config validate() functions. Every message has the form "key = value: rule",
// and numbers print as a config file would write them (0.25, 2.1e-09, -1), never "0.250000".
//
//   require(cycle_s > 0.0 && cycle_s <= 60.0, "command.cycle_s", cycle_s, "must be in (0, 60]");
//   check_range("sog", "noise_relative", noise_relative, 0.0, 1.0);
#include <string>
#include <type_traits>

namespace sarloc {

/// The shortest text that reads back as `value` (std::to_chars).
std::string config_value(double value);

/// ConfigError "key = value: rule" unless `ok`. Strings are quoted: "key = 'text': rule".
void require(bool ok, const std::string& key, const std::string& value, const std::string& rule);
inline void require(bool ok, const std::string& key, const char* value, const std::string& rule) {
  require(ok, key, std::string(value), rule);
}
template <typename Number, typename = std::enable_if_t<std::is_arithmetic_v<Number>>>
void require(bool ok, const std::string& key, Number value, const std::string& rule);

/// A finite value within [lo, hi], else ConfigError "section.key = value: must be within [lo, hi]".
void check_range(const char* section, const char* key, double value, double lo, double hi);

namespace detail {
[[noreturn]] void throw_config_error(const std::string& key, const std::string& value_text, const std::string& rule);
}  // namespace detail

template <typename Number, typename>
void require(bool ok, const std::string& key, Number value, const std::string& rule) {
  if (ok) return;
  if constexpr (std::is_floating_point_v<Number>) {
    detail::throw_config_error(key, config_value(static_cast<double>(value)), rule);
  } else if constexpr (std::is_same_v<Number, bool>) {
    detail::throw_config_error(key, value ? "true" : "false", rule);
  } else {
    detail::throw_config_error(key, std::to_string(value), rule);
  }
}

}  // namespace sarloc
