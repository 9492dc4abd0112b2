#include "sarloc/core/avalanche/bearing_density.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"

namespace sarloc::avalanche {
namespace {
constexpr double kBinWidth = 2.0 * kPi / BearingDensity::kBins;

// Bearing of a hypothesis's mean from the receiver; none for a mean on the receiver's vertical.
std::optional<double> bearing_of(const TransmitterHypothesis& c) {
  const double x = c.position.x();
  const double y = c.position.y();
  if (x == 0.0 && y == 0.0) return std::nullopt;
  return std::atan2(y, x);
}
}  // namespace

int BearingDensity::bin_of(double bearing_rad) {
  const int b = static_cast<int>(std::floor((wrap_angle(bearing_rad) + kPi) / kBinWidth));
  return std::clamp(b, 0, kBins - 1);
}

BearingDensity::BearingDensity(const std::vector<TransmitterHypothesis>& hypotheses,
                               double kernel_sigma_rad) {
  std::array<double, kBins> mass{};
  for (const TransmitterHypothesis& c : hypotheses) {
    if (const auto bearing = bearing_of(c)) mass[bin_of(*bearing)] += c.weight;
  }
  // Von Mises kernel exp(kappa (cos d - 1)), kappa = 1 / sigma^2, tabulated by bin offset.
  const double kappa = 1.0 / (kernel_sigma_rad * kernel_sigma_rad);
  std::array<double, kBins> kernel{};
  for (int d = 0; d < kBins; ++d) kernel[d] = std::exp(kappa * (std::cos(d * kBinWidth) - 1.0));
  for (int j = 0; j < kBins; ++j) {
    double s = 0.0;
    for (int k = 0; k < kBins; ++k) s += mass[k] * kernel[(j - k + kBins) % kBins];
    smoothed_[j] = s;
  }
  peak_bin_ = static_cast<int>(std::max_element(smoothed_.begin(), smoothed_.end()) - smoothed_.begin());
}

BearingAgreement bearing_agreement(const std::vector<TransmitterHypothesis>& hypotheses,
                                   double true_bearing_rad) {
  BearingAgreement a;
  double total = 0.0;
  for (const TransmitterHypothesis& c : hypotheses) {
    const auto bearing = bearing_of(c);
    if (!bearing) continue;
    const double w = c.weight;
    const double cosine = std::cos(*bearing - true_bearing_rad);
    total += w;
    a.mean_cosine += w * cosine;
    if (cosine > std::cos(kPi / 4.0)) a.mass_within_45deg += w;
  }
  if (total > 0.0) {
    a.mean_cosine /= total;
    a.mass_within_45deg /= total;
  }
  return a;
}

double BearingDensity::at(double bearing_rad) const { return smoothed_[bin_of(bearing_rad)]; }

double BearingDensity::peak() const { return -kPi + (peak_bin_ + 0.5) * kBinWidth; }

}  // namespace sarloc::avalanche
