#pragma once
// Numbers in sentences and drawings people read: positions, radii and times to a tenth.
#include <cstdio>
#include <string>

namespace sarloc {

/// "12.3", "-5.0": one decimal, the locale's "C" point.
inline std::string one_decimal(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", v);
  return buffer;
}

}  // namespace sarloc
