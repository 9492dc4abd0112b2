#pragma once
// Posterior density of the horizontal bearing from the receiver to the transmitter, read off
// the SOG mixture: component weights binned by the bearing of their mean (5-degree bins) and
// smoothed with a von Mises kernel. Used by the opening phase of the search, where the mixture
// is a ring or several arcs and its mean (eq. 18) sits between them, pointing nowhere useful.
//
//   BearingDensity d(filter.hypotheses(), 35.0 * kPi / 180.0);
//   double heading = d.peak();            // most probable bearing in G
//   if (d.at(current) * 2.0 >= d.at(heading)) heading = current;   // hysteresis
#include <array>
#include <vector>

#include "sarloc/core/avalanche/transmitter_hypothesis.hpp"

namespace sarloc::avalanche {

class BearingDensity {
 public:
  static constexpr int kBins = 72;

  /// `kernel_sigma_rad` > 0: angular width of the smoothing kernel.
  BearingDensity(const std::vector<TransmitterHypothesis>& hypotheses, double kernel_sigma_rad);

  /// Smoothed probability mass around `bearing_rad` (any angle; wrapped).
  double at(double bearing_rad) const;
  /// Bearing (rad, in (-pi, pi]) of the bin with the largest smoothed mass.
  double peak() const;

 private:
  static int bin_of(double bearing_rad);
  std::array<double, kBins> smoothed_{};
  int peak_bin_ = 0;
};

/// How well a mixture's bearing posterior agrees with a known true bearing (evaluation only:
/// sarloc-eval --trace-csv). 0.25 / 0 for a uniform ring, 1 / 1 when certain and right.
struct BearingAgreement {
  double mass_within_45deg = 0.0;  ///< weight of components whose bearing is within 45 deg
  double mean_cosine = 0.0;        ///< weighted mean of cos(component bearing - true bearing)
};
BearingAgreement bearing_agreement(const std::vector<TransmitterHypothesis>& hypotheses,
                                   double true_bearing_rad);

}  // namespace sarloc::avalanche
