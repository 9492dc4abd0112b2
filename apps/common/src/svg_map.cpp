#include "sarloc/app/svg_map.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/number_text.hpp"

namespace sarloc::app {

namespace {

constexpr double kTitle_px = 22.0;

}  // namespace

std::string escape_html(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

SvgMap::SvgMap(Eigen::Vector2d min, Eigen::Vector2d max, double width_px, double margin_m, std::string title)
    : min_(min - Eigen::Vector2d::Constant(margin_m)),
      max_(max + Eigen::Vector2d::Constant(margin_m)),
      title_(std::move(title)) {
  Eigen::Vector2d span = (max_ - min_).cwiseMax(1.0);
  max_ = min_ + span;
  scale_ = width_px / span.x();
  // Keep maps of long thin fields readable: at most 1.2 times as tall as wide.
  scale_ = std::min(scale_, 1.2 * width_px / span.y());
  width_px_ = span.x() * scale_;
  height_px_ = span.y() * scale_ + kTitle_px;
}

Eigen::Vector2d SvgMap::px(const Eigen::Vector2d& m) const {
  return {(m.x() - min_.x()) * scale_, kTitle_px + (max_.y() - m.y()) * scale_};
}

void SvgMap::polyline(const std::vector<Eigen::Vector2d>& points, const std::string& colour, double width_px,
                      const std::string& dash, double opacity) {
  if (points.size() < 2) return;
  body_ += "<polyline fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"" + one_decimal(width_px) +
           "\" stroke-opacity=\"" + one_decimal(opacity) + "\"" +
           (dash.empty() ? "" : " stroke-dasharray=\"" + dash + "\"") + " points=\"";
  for (const auto& p : points) {
    const auto q = px(p);
    body_ += one_decimal(q.x()) + "," + one_decimal(q.y()) + " ";
  }
  body_ += "\"/>\n";
}

void SvgMap::image(const Eigen::Vector2d& north_west, double width_m, double height_m, const std::string& href) {
  const auto p = px(north_west);
  // Half a pixel over its right and bottom edges: neighbours drawn edge to edge leave an
  // anti-aliased hairline between them.
  auto px2 = [](double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.2f", v);
    return std::string(buffer);
  };
  under_ += "<image x=\"" + px2(p.x()) + "\" y=\"" + px2(p.y()) + "\" width=\"" + px2(width_m * scale_ + 0.5) +
            "\" height=\"" + px2(height_m * scale_ + 0.5) + "\" preserveAspectRatio=\"none\" href=\"" +
            escape_html(href) + "\"/>\n";
}

void SvgMap::polygon(const std::vector<Eigen::Vector2d>& points, const std::string& colour, double fill_opacity) {
  if (points.size() < 3) return;
  body_ += "<polygon stroke=\"" + colour + "\" stroke-width=\"1.5\" fill=\"" + colour + "\" fill-opacity=\"" +
           one_decimal(fill_opacity) + "\" points=\"";
  for (const auto& p : points) {
    const auto q = px(p);
    body_ += one_decimal(q.x()) + "," + one_decimal(q.y()) + " ";
  }
  body_ += "\"/>\n";
}

void SvgMap::line(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const std::string& colour, double width_px) {
  const auto p = px(a), q = px(b);
  body_ += "<line x1=\"" + one_decimal(p.x()) + "\" y1=\"" + one_decimal(p.y()) + "\" x2=\"" + one_decimal(q.x()) +
           "\" y2=\"" + one_decimal(q.y()) + "\" stroke=\"" + colour + "\" stroke-width=\"" + one_decimal(width_px) +
           "\" stroke-linecap=\"round\"/>\n";
}

void SvgMap::dot(const Eigen::Vector2d& p, double radius_px, const std::string& colour, double opacity) {
  const auto q = px(p);
  body_ += "<circle cx=\"" + one_decimal(q.x()) + "\" cy=\"" + one_decimal(q.y()) + "\" r=\"" + one_decimal(radius_px) +
           "\" fill=\"" + colour + "\" fill-opacity=\"" + one_decimal(opacity) + "\"/>\n";
}

void SvgMap::ellipse95(const Eigen::Vector2d& centre, const Eigen::Matrix2d& covariance, const std::string& colour,
                       double opacity, bool filled) {
  const Ellipse95 e = sarloc::ellipse95(covariance);  // the free function, not this member
  const double a = e.semi_major_m * scale_, b = e.semi_minor_m * scale_;
  // SVG's y points down: the angle flips sign.
  const double angle_deg = -e.major_angle_rad * 180.0 / kPi;
  const auto q = px(centre);
  body_ += "<ellipse cx=\"" + one_decimal(q.x()) + "\" cy=\"" + one_decimal(q.y()) + "\" rx=\"" +
           one_decimal(std::max(a, 0.5)) + "\" ry=\"" + one_decimal(std::max(b, 0.5)) + "\" transform=\"rotate(" +
           one_decimal(angle_deg) + " " + one_decimal(q.x()) + " " + one_decimal(q.y()) + ")\" stroke=\"" + colour +
           "\" stroke-opacity=\"" + one_decimal(opacity) + "\" fill=\"" + (filled ? colour : "none") +
           "\" fill-opacity=\"" + one_decimal(filled ? 0.15 * opacity : 0.0) + "\"/>\n";
}

void SvgMap::cross(const Eigen::Vector2d& p, double size_px, const std::string& colour) {
  const auto q = px(p);
  const std::string a = one_decimal(q.x() - size_px), b = one_decimal(q.x() + size_px),
                    c = one_decimal(q.y() - size_px), d = one_decimal(q.y() + size_px);
  body_ += "<path d=\"M" + a + " " + c + " L" + b + " " + d + " M" + a + " " + d + " L" + b + " " + c + "\" stroke=\"" +
           colour + "\" stroke-width=\"2.5\"/>\n";
}

void SvgMap::label(const Eigen::Vector2d& p, const std::string& text, const std::string& colour, double dx_px,
                   double dy_px) {
  const auto q = px(p);
  body_ += "<text x=\"" + one_decimal(q.x() + dx_px) + "\" y=\"" + one_decimal(q.y() + dy_px) + "\" fill=\"" + colour +
           "\" font-size=\"12\">" + escape_html(text) + "</text>\n";
}

std::string SvgMap::finish() const {
  // A scale bar of a round length near a fifth of the width.
  const double target_m = (max_.x() - min_.x()) / 5.0;
  const double base_m = std::pow(10.0, std::floor(std::log10(target_m)));
  double bar_m = base_m;
  for (const double f : {2.0, 5.0}) {
    if (base_m * f <= target_m) bar_m = base_m * f;
  }
  const double bar_px = bar_m * scale_;
  const double y = height_px_ - 12.0;
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"map\" width=\"" + one_decimal(width_px_) +
                    "\" height=\"" + one_decimal(height_px_) + "\" viewBox=\"0 0 " + one_decimal(width_px_) + " " +
                    one_decimal(height_px_) + "\" role=\"img\">\n";
  svg += "<rect x=\"0\" y=\"" + one_decimal(kTitle_px) + "\" width=\"" + one_decimal(width_px_) + "\" height=\"" +
         one_decimal(height_px_ - kTitle_px) + "\" fill=\"#f7f9fb\" stroke=\"#9aa5b1\"/>\n";
  svg += "<text x=\"4\" y=\"16\" font-size=\"14\" font-weight=\"bold\">" + escape_html(title_) + "</text>\n";
  if (!under_.empty()) {
    // The basemap, cut to the map's frame (a tile reaches past it), under everything else.
    const std::string area_height = one_decimal(height_px_ - kTitle_px);
    svg += "<svg x=\"0\" y=\"" + one_decimal(kTitle_px) + "\" width=\"" + one_decimal(width_px_) + "\" height=\"" +
           area_height + "\" viewBox=\"0 " + one_decimal(kTitle_px) + " " + one_decimal(width_px_) + " " + area_height +
           "\" class=\"basemap\">\n" + under_ + "</svg>\n";
  }
  svg += body_;
  svg += "<line x1=\"10\" y1=\"" + one_decimal(y) + "\" x2=\"" + one_decimal(10 + bar_px) + "\" y2=\"" +
         one_decimal(y) + "\" stroke=\"#111\" stroke-width=\"3\"/>\n";
  svg += "<text x=\"10\" y=\"" + one_decimal(y - 5) + "\" font-size=\"11\">" + one_decimal(bar_m) + " m</text>\n";
  svg += "<text x=\"" + one_decimal(width_px_ - 18) + "\" y=\"" + one_decimal(kTitle_px + 16) +
         "\" font-size=\"13\" font-weight=\"bold\">N</text>\n";
  svg += "<path d=\"M" + one_decimal(width_px_ - 14) + " " + one_decimal(kTitle_px + 20) +
         " l-5 12 l10 0 z\" fill=\"#111\"/>\n";
  svg += "</svg>\n";
  return svg;
}

}  // namespace sarloc::app
