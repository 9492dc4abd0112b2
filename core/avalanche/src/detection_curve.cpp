#include "sarloc/core/avalanche/detection_curve.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <boost/math/distributions/non_central_chi_squared.hpp>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {
constexpr double kDegreesOfFreedom = 6.0;  // three complex axes
constexpr std::size_t kEntries = 512;
}  // namespace

DetectionCurve::DetectionCurve(double threshold) : threshold_(threshold) {
  if (!std::isfinite(threshold) || threshold <= 0.0 || threshold > 1e4) {
    std::ostringstream os;
    os << "detection threshold = " << threshold << ": must be in (0, 1e4]";
    throw ConfigError(os.str());
  }
  // Far enough that the statistic's mean (6 + lambda) exceeds the threshold by 10 of its sigmas.
  double end = threshold;
  while (kDegreesOfFreedom + end - 10.0 * std::sqrt(2.0 * (kDegreesOfFreedom + 2.0 * end)) < threshold) end *= 1.5;
  step_ = std::sqrt(end) / static_cast<double>(kEntries - 1);
  table_.reserve(kEntries);
  table_.push_back(boost::math::cdf(boost::math::complement(boost::math::chi_squared(kDegreesOfFreedom), threshold)));
  for (std::size_t i = 1; i < kEntries; ++i) {
    const double s = step_ * static_cast<double>(i);
    const boost::math::non_central_chi_squared d(kDegreesOfFreedom, s * s);
    table_.push_back(boost::math::cdf(boost::math::complement(d, threshold)));
  }
}

double DetectionCurve::probability(double noncentrality) const {
  if (!(noncentrality > 0.0)) return table_.front();
  const double u = std::sqrt(noncentrality) / step_;
  if (u >= static_cast<double>(kEntries - 1)) return 1.0;
  const auto i = static_cast<std::size_t>(u);
  const double f = u - static_cast<double>(i);
  return std::clamp(table_[i] + f * (table_[i + 1] - table_[i]), 0.0, 1.0);
}

}  // namespace sarloc::avalanche
