#include "sarloc/core/common/validate.hpp"

#include <cmath>
#include <sstream>

#include "sarloc/core/common/errors.hpp"

namespace sarloc {

void check_range(const char* section, const char* key, double value, double lo, double hi) {
  if (std::isfinite(value) && value >= lo && value <= hi) return;
  std::ostringstream out;
  out << section << "." << key << " = " << value << ": must be within [" << lo << ", " << hi << "]";
  throw ConfigError(out.str());
}

}  // namespace sarloc
