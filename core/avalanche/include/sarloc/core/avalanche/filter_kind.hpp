#pragma once
// Which transmitter filter a search runs (docs/estimation/baselines.md).
#include <string>

namespace sarloc::avalanche {

enum class FilterKind { kSog, kPf, kRbpf, kRbpfImproved, kGrid };

/// "sog", "pf", "rbpf", "rbpf-improved", "grid".
const char* to_string(FilterKind kind);
/// Throws ConfigError "<key> = text: must be one of sog, pf, rbpf, rbpf-improved, grid".
FilterKind parse_filter_kind(const std::string& text, const std::string& key);
/// Every kind, in the order of the comparison tables.
inline constexpr FilterKind kAllFilterKinds[] = {FilterKind::kSog, FilterKind::kPf, FilterKind::kRbpf,
                                                 FilterKind::kRbpfImproved, FilterKind::kGrid};

}  // namespace sarloc::avalanche
