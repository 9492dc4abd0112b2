#pragma once
// Order statistics shared by every evaluation and benchmark.
#include <vector>

namespace sarloc {

/// The q-quantile (q in [0, 1]) by linear interpolation between order statistics; 0 when empty.
double percentile(std::vector<double> values, double q);

}  // namespace sarloc
