#include "sarloc/core/avalanche/filter_kind.hpp"

#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {

const char* to_string(FilterKind kind) {
  switch (kind) {
    case FilterKind::kSog: return "sog";
    case FilterKind::kPf: return "pf";
    case FilterKind::kRbpf: return "rbpf";
    case FilterKind::kRbpfImproved: return "rbpf-improved";
    case FilterKind::kGrid: return "grid";
  }
  return "?";
}

FilterKind parse_filter_kind(const std::string& text, const std::string& key) {
  for (FilterKind k : kAllFilterKinds)
    if (text == to_string(k)) return k;
  throw ConfigError(key + " = " + text + ": must be one of sog, pf, rbpf, rbpf-improved, grid");
}

}  // namespace sarloc::avalanche
