#include "sarloc/core/common/validate.hpp"

#include <charconv>
#include <cmath>

#include "sarloc/core/common/errors.hpp"

namespace sarloc {

std::string config_value(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

namespace detail {

void throw_config_error(const std::string& key, const std::string& value_text, const std::string& rule) {
  throw ConfigError(key + " = " + value_text + ": " + rule);
}

}  // namespace detail

void require(bool ok, const std::string& key, const std::string& value, const std::string& rule) {
  if (!ok) detail::throw_config_error(key, "'" + value + "'", rule);
}

void check_range(const char* section, const char* key, double value, double lo, double hi) {
  require(std::isfinite(value) && value >= lo && value <= hi, std::string(section) + "." + key, value,
          "must be within [" + config_value(lo) + ", " + config_value(hi) + "]");
}

}  // namespace sarloc
