#include "error_histogram.hpp"

#include <algorithm>
#include <array>
#include <sstream>

namespace sarloc::eval {

std::string error_histogram_svg(const std::vector<avalanche::EvaluationSummary>& filters) {
  constexpr int kBins = 11;  // [0, 0.1), ..., [0.9, 1.0), > 1 m
  constexpr double kPanelW = 230, kPanelH = 200, kLeft = 50, kTop = 60, kGap = 40;
  std::vector<std::array<int, kBins>> counts;
  int y_max = 1;
  for (const auto& f : filters) {
    std::array<int, kBins> c{};
    for (const auto& t : f.per_trial) ++c[std::min(kBins - 1, static_cast<int>(t.error_m / 0.1))];
    y_max = std::max(y_max, *std::max_element(c.begin(), c.end()));
    counts.push_back(c);
  }
  y_max = (y_max + 9) / 10 * 10;
  std::ostringstream svg;
  const double width = kLeft + filters.size() * (kPanelW + kGap);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << kTop + kPanelH + 60
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!filters.empty()) {
    svg << "<text x=\"" << kLeft << "\" y=\"22\" font-size=\"15\">Final error per trial, " << filters.front().receiver
        << " receiver, " << filters.front().trials << " trials, seed " << filters.front().seed
        << " (the same trials for every filter; last bin: error &gt; 1 m)</text>\n";
  }
  for (std::size_t f = 0; f < filters.size(); ++f) {
    const double x0 = kLeft + f * (kPanelW + kGap);
    const double bar = kPanelW / kBins;
    svg << "<text x=\"" << x0 << "\" y=\"" << kTop - 12 << "\">" << filters[f].filter << ": median "
        << static_cast<int>(filters[f].error_m.median * 100 + 0.5) / 100.0 << " m, &gt; 1 m in "
        << filters[f].errors_over_1m << "</text>\n";
    svg << "<rect x=\"" << x0 << "\" y=\"" << kTop << "\" width=\"" << kPanelW << "\" height=\"" << kPanelH
        << "\" fill=\"none\" stroke=\"black\"/>\n";
    for (int b = 0; b < kBins; ++b) {
      const double h = kPanelH * counts[f][b] / y_max;
      svg << "<rect x=\"" << x0 + b * bar + 1 << "\" y=\"" << kTop + kPanelH - h << "\" width=\"" << bar - 2
          << "\" height=\"" << h << "\" fill=\"" << (b == kBins - 1 ? "#d62728" : "#1f77b4") << "\"/>\n";
    }
    for (int b = 0; b <= kBins - 1; b += 5)
      svg << "<text x=\"" << x0 + b * bar << "\" y=\"" << kTop + kPanelH + 16 << "\" text-anchor=\"middle\">"
          << b / 10.0 << "</text>\n";
    svg << "<text x=\"" << x0 + (kBins - 0.5) * bar << "\" y=\"" << kTop + kPanelH + 16
        << "\" text-anchor=\"middle\">&gt;1</text>\n";
    svg << "<text x=\"" << x0 + kPanelW / 2 << "\" y=\"" << kTop + kPanelH + 34
        << "\" text-anchor=\"middle\">error (m)</text>\n";
    svg << "<text x=\"" << x0 - 6 << "\" y=\"" << kTop + 4 << "\" text-anchor=\"end\">" << y_max << "</text>\n";
    svg << "<text x=\"" << x0 - 6 << "\" y=\"" << kTop + kPanelH << "\" text-anchor=\"end\">0</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace sarloc::eval
