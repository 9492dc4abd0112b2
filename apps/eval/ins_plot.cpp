#include "ins_plot.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace sarloc::eval {
namespace {

std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

}  // namespace

std::string ins_plot_svg(const firefighter::InsRecording& input, const std::string& title,
                         const std::vector<Eigen::Vector2d>& footprints, double turn_rad) {
  firefighter::InsRecording run = input;
  if (!footprints.empty() && !run.stances.empty()) {
    const Eigen::Vector3d origin = run.stances.front().p;
    const Eigen::Matrix2d r = Eigen::Rotation2Dd(turn_rad).toRotationMatrix();
    auto place = [&](Eigen::Vector3d& p) { p.head<2>() = footprints.front() + r * (p - origin).head<2>(); };
    for (auto& t : run.track) place(t.p);
    for (auto& s : run.stances) place(s.p);
  }
  constexpr double kTop = 50, kLeft = 60, kMap = 460, kGap = 80, kHeightW = 460, kHeightH = 220;
  // Top view: equal scale on both axes, the track and footprints inside.
  Eigen::Vector2d lo(0, 0), hi(0, 0);
  for (const auto& p : run.track) {
    lo = lo.cwiseMin(p.p.head<2>());
    hi = hi.cwiseMax(p.p.head<2>());
  }
  for (const auto& f : footprints) {
    lo = lo.cwiseMin(f);
    hi = hi.cwiseMax(f);
  }
  const double span = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1.0}) * 1.05;
  const Eigen::Vector2d mid = 0.5 * (lo + hi);
  auto mx = [&](double x) { return kLeft + kMap * (0.5 + (x - mid.x()) / span); };
  auto my = [&](double y) { return kTop + kMap * (0.5 - (y - mid.y()) / span); };
  std::ostringstream svg;
  svg << std::fixed << std::setprecision(2);
  // At most about 1500 points a curve: a readable picture, a small file.
  const std::size_t every = std::max<std::size_t>(1, run.track.size() / 1500);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kLeft + kMap + kGap + kHeightW + 40 << "\" height=\""
      << kTop + kMap + 60 << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg << "<text x=\"" << kLeft << "\" y=\"22\" font-size=\"15\">" << escaped(title) << "</text>\n";
  svg << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << kMap << "\" height=\"" << kMap
      << "\" fill=\"none\" stroke=\"black\"/>\n";
  svg << "<text x=\"" << kLeft << "\" y=\"" << kTop - 8 << "\">top view (x, y; " << std::lround(span)
      << " m across)</text>\n";
  svg << "<polyline fill=\"none\" stroke=\"#1f77b4\" stroke-width=\"1.5\" points=\"";
  for (std::size_t i = 0; i < run.track.size(); i += every)
    svg << mx(run.track[i].p.x()) << "," << my(run.track[i].p.y()) << " ";
  svg << "\"/>\n";
  for (const auto& s : run.stances)
    svg << "<circle cx=\"" << mx(s.p.x()) << "\" cy=\"" << my(s.p.y()) << "\" r=\"2\" fill=\"#1f77b4\"/>\n";
  for (const auto& f : footprints)
    svg << "<circle cx=\"" << mx(f.x()) << "\" cy=\"" << my(f.y()) << "\" r=\"3\" fill=\"none\" stroke=\"#d62728\"/>\n";
  svg << "<text x=\"" << kLeft << "\" y=\"" << kTop + kMap + 20
      << "\">blue: the INS track, dots its stance phases; start at (0, 0)"
      << (footprints.empty() ? "" : "; red rings: footprint truth") << "</text>\n";
  // Height against time.
  const double x0 = kLeft + kMap + kGap;
  double z_lo = -0.1, z_hi = 0.1, t0 = 0.0, t1 = 1.0;
  if (!run.track.empty()) {
    t0 = run.track.front().t;
    t1 = std::max(run.track.back().t, t0 + 1.0);
  }
  for (const auto& p : run.track) {
    z_lo = std::min(z_lo, p.p.z());
    z_hi = std::max(z_hi, p.p.z());
  }
  auto hx = [&](double t) { return x0 + kHeightW * (t - t0) / (t1 - t0); };
  auto hy = [&](double z) { return kTop + kHeightH * (1.0 - (z - z_lo) / (z_hi - z_lo)); };
  svg << "<rect x=\"" << x0 << "\" y=\"" << kTop << "\" width=\"" << kHeightW << "\" height=\"" << kHeightH
      << "\" fill=\"none\" stroke=\"black\"/>\n";
  svg << "<text x=\"" << x0 << "\" y=\"" << kTop - 8 << "\">height z (m) against time (s)</text>\n";
  svg << "<line x1=\"" << x0 << "\" x2=\"" << x0 + kHeightW << "\" y1=\"" << hy(0) << "\" y2=\"" << hy(0)
      << "\" stroke=\"#ddd\"/>\n";
  svg << "<text x=\"" << x0 - 6 << "\" y=\"" << hy(z_hi) + 10 << "\" text-anchor=\"end\">"
      << std::round(z_hi * 100) / 100 << "</text><text x=\"" << x0 - 6 << "\" y=\"" << hy(z_lo)
      << "\" text-anchor=\"end\">" << std::round(z_lo * 100) / 100 << "</text>\n";
  svg << "<text x=\"" << x0 << "\" y=\"" << kTop + kHeightH + 16 << "\">" << std::round(t0) << "</text><text x=\""
      << x0 + kHeightW << "\" y=\"" << kTop + kHeightH + 16 << "\" text-anchor=\"end\">" << std::round(t1)
      << "</text>\n";
  svg << "<polyline fill=\"none\" stroke=\"#2ca02c\" stroke-width=\"1.2\" points=\"";
  for (std::size_t i = 0; i < run.track.size(); i += every)
    svg << hx(run.track[i].t) << "," << hy(run.track[i].p.z()) << " ";
  svg << "\"/>\n</svg>\n";
  return svg.str();
}

}  // namespace sarloc::eval
