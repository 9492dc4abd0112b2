#pragma once
// Ids (rescuer, team, responder, sector, incident, mission, operator) name files, URL paths, DDS
// partitions and page elements, and arrive from YAML and from any participant on the domain.
// One rule for all of them, checked at load and at the DDS boundary: 1-64 characters from
// [A-Za-z0-9_.-]. Nothing else gets in, so nothing downstream has to escape an id or cope
// with bytes that are not UTF-8 (a responder id "bad\xff\xfe" once killed the dashboard).
#include <cstddef>
#include <string>
#include <string_view>

namespace sarloc {

inline constexpr std::size_t kIdentifierMax = 64;  // the IDL's ID_MAX

/// 1-kIdentifierMax characters, each a letter, a digit, '_', '.' or '-'.
bool is_identifier(std::string_view value);

/// `value` as a quoted, printable excerpt for error messages: bytes outside printable ASCII
/// as \xNN, at most 40 of them shown (the rest counted).
std::string printable_excerpt(std::string_view value);

/// "" when `value` is an identifier (or empty and `empty_allowed`), else the message
/// "<field> = '<excerpt>': not an identifier (1-64 of A-Z a-z 0-9 _ . -)".
std::string identifier_problem(std::string_view value, const std::string& field, bool empty_allowed = false);

/// Throws InputError "<field> = '<excerpt>': not an identifier (1-64 of A-Z a-z 0-9 _ . -)".
/// `empty_allowed`: an optional id (no team, nobody yet) may be "".
void check_identifier(std::string_view value, const std::string& field, bool empty_allowed = false);

}  // namespace sarloc
