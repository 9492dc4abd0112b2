#pragma once
// The one range check of config validate() functions: a finite value within [lo, hi], else
// ConfigError "section.key = value: must be within [lo, hi]".
#include <string>

namespace sarloc {

void check_range(const char* section, const char* key, double value, double lo, double hi);

}  // namespace sarloc
