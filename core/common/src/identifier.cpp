#include "sarloc/core/common/identifier.hpp"

#include <cstdio>

#include "sarloc/core/common/errors.hpp"

namespace sarloc {

bool is_identifier(std::string_view value) {
  if (value.empty() || value.size() > kIdentifierMax) return false;
  for (const char c : value) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.' || c == '-';
    if (!ok) return false;
  }
  return true;
}

std::string printable_excerpt(std::string_view value) {
  constexpr std::size_t kShown = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < value.size() && i < kShown; ++i) {
    const auto byte = static_cast<unsigned char>(value[i]);
    if (byte >= 0x20 && byte < 0x7F && byte != '\\' && byte != '\'') {
      out += static_cast<char>(byte);
    } else {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02X", byte);
      out += hex;
    }
  }
  out += "'";
  if (value.size() > kShown) out += " (+" + std::to_string(value.size() - kShown) + " bytes)";
  return out;
}

std::string identifier_problem(std::string_view value, const std::string& field, bool empty_allowed) {
  if ((value.empty() && empty_allowed) || is_identifier(value)) return {};
  return field + " = " + printable_excerpt(value) + ": not an identifier (1-64 of A-Z a-z 0-9 _ . -)";
}

void check_identifier(std::string_view value, const std::string& field, bool empty_allowed) {
  if (auto problem = identifier_problem(value, field, empty_allowed); !problem.empty()) throw InputError(problem);
}

}  // namespace sarloc
