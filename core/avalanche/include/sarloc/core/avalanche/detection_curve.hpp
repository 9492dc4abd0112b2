#pragma once
// How likely the receiver is to hear one pulse of a tracked transmitter (issue 12, negative
// information: a pulse that was due and not heard says where the transmitter is not).
//
// The pulse detector (pulse_detector.hpp) whitens each axis by its noise and sums a 70 ms
// window: under noise its statistic is chi-square with 6 degrees of freedom (three complex
// axes); under a pulse of real amplitude h (receiver frame) it is non-central chi-square with
// noncentrality lambda = sum_i (h_i / sigma_i)^2, sigma_i the axis's noise per 70 ms pulse. The
// pulse is detected when the statistic exceeds the threshold of the tracked carrier's search.
// Boost.Math gives the distribution; a table on sqrt(lambda) keeps the filter's per-component
// cost to an interpolation.
//
//   DetectionCurve curve(41.5);
//   double p = curve.probability(lambda);   // P(statistic > 41.5)
#include <vector>

namespace sarloc::avalanche {

class DetectionCurve {
 public:
  /// threshold: of the statistic, > 0 (throws ConfigError otherwise).
  explicit DetectionCurve(double threshold);

  /// P(detected | noncentrality lambda >= 0); 1 beyond the table.
  double probability(double noncentrality) const;
  double threshold() const { return threshold_; }

 private:
  double threshold_;
  double step_;                 ///< table spacing in sqrt(lambda)
  std::vector<double> table_;   ///< probability at sqrt(lambda) = i * step_
};

}  // namespace sarloc::avalanche
