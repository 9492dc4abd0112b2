#include "rmse_plot.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace sarloc::eval {
namespace {

constexpr const char* kColours[] = {"#7f7f7f", "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b"};

std::string suffix(const std::string& name) {
  const auto slash = name.find('/');
  return slash == std::string::npos ? name : name.substr(slash + 1);
}

}  // namespace

std::string rmse_plot_svg(const firefighter::FirefighterSummary& s, double every_s) {
  constexpr double kPanelW = 420, kPanelH = 300, kLeft = 60, kTop = 50, kGap = 90;
  double y_max = 1.0;
  for (const auto& v : s.variants) {
    for (double r : v.rmse_at_s) y_max = std::max(y_max, r);
  }
  y_max = std::min(std::ceil(y_max), 20.0);
  const double t_max = every_s * static_cast<double>(s.variants.empty() ? 1 : s.variants.front().rmse_at_s.size());
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << 2 * kPanelW + kGap + kLeft + 40 << "\" height=\""
      << kPanelH + kTop + 110 << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg << "<text x=\"" << kLeft << "\" y=\"22\" font-size=\"15\">" << s.building << ": horizontal RMSE against time, "
      << s.members << " firefighters (" << s.runs << " teams of two), seed " << s.seed << "</text>\n";
  for (int panel = 0; panel < 2; ++panel) {
    const bool known = panel == 0;
    const double x0 = kLeft + panel * (kPanelW + kGap);
    auto px = [&](double t) { return x0 + kPanelW * t / t_max; };
    auto py = [&](double r) { return kTop + kPanelH * (1.0 - std::min(r, y_max) / y_max); };
    svg << "<text x=\"" << x0 << "\" y=\"" << kTop - 10 << "\">(" << (known ? "a" : "b") << ") "
        << (known ? "known" : "unknown") << " initial state</text>\n";
    svg << "<rect x=\"" << x0 << "\" y=\"" << kTop << "\" width=\"" << kPanelW << "\" height=\"" << kPanelH
        << "\" fill=\"none\" stroke=\"black\"/>\n";
    for (double r = 0; r <= y_max + 1e-9; r += y_max > 8 ? 2.0 : 1.0) {
      svg << "<line x1=\"" << x0 << "\" x2=\"" << x0 + kPanelW << "\" y1=\"" << py(r) << "\" y2=\"" << py(r)
          << "\" stroke=\"#ddd\"/><text x=\"" << x0 - 8 << "\" y=\"" << py(r) + 4 << "\" text-anchor=\"end\">" << r
          << "</text>\n";
    }
    for (double t = 0; t <= t_max + 1e-9; t += 60.0) {
      svg << "<text x=\"" << px(t) << "\" y=\"" << kTop + kPanelH + 16 << "\" text-anchor=\"middle\">" << t
          << "</text>\n";
    }
    svg << "<text x=\"" << x0 + kPanelW / 2 << "\" y=\"" << kTop + kPanelH + 34
        << "\" text-anchor=\"middle\">time (s)</text>\n";
    svg << "<text transform=\"translate(" << x0 - 40 << "," << kTop + kPanelH / 2
        << ") rotate(-90)\" text-anchor=\"middle\">RMSE (m)</text>\n";
    int colour = 0, legend = 0;
    for (const auto& v : s.variants) {
      if (v.variant.known_initial_state != known) continue;
      const char* c = kColours[colour++ % 6];
      svg << "<polyline fill=\"none\" stroke=\"" << c << "\" stroke-width=\"2\" points=\"";
      for (std::size_t j = 0; j < v.rmse_at_s.size(); ++j) svg << px(every_s * (j + 1)) << "," << py(v.rmse_at_s[j]) << " ";
      svg << "\"/>\n";
      const double ly = kTop + kPanelH + 52 + 16 * legend++;
      svg << "<line x1=\"" << x0 << "\" x2=\"" << x0 + 24 << "\" y1=\"" << ly - 4 << "\" y2=\"" << ly - 4
          << "\" stroke=\"" << c << "\" stroke-width=\"2\"/><text x=\"" << x0 + 30 << "\" y=\"" << ly << "\">"
          << suffix(v.variant.name) << "</text>\n";
    }
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace sarloc::eval
