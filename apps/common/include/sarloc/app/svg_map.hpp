#pragma once
// A map in SVG (the report, a floor plan's plot): metres (x east, y north) to pixels, with
// north up, a scale bar and a north arrow. Every drawing call appends one SVG element.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace sarloc::app {

class SvgMap {
 public:
  /// A map of the box [min, max] (metres, padded by `margin_m`) drawn `width_px` wide.
  SvgMap(Eigen::Vector2d min, Eigen::Vector2d max, double width_px, double margin_m, std::string title);

  void polyline(const std::vector<Eigen::Vector2d>& points, const std::string& colour, double width_px,
                const std::string& dash = "", double opacity = 1.0);
  /// An image (a basemap tile: its north-west corner and size in metres), under every other
  /// drawing and cut to the map's frame. `href` is a data: URI: the report loads nothing.
  void image(const Eigen::Vector2d& north_west, double width_m, double height_m, const std::string& href);
  /// A closed outline, filled (an area: the avalanche deposit).
  void polygon(const std::vector<Eigen::Vector2d>& points, const std::string& colour, double fill_opacity);
  void line(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const std::string& colour, double width_px);
  void dot(const Eigen::Vector2d& p, double radius_px, const std::string& colour, double opacity = 1.0);
  /// The 95 % ellipse of a horizontal covariance around `centre`.
  void ellipse95(const Eigen::Vector2d& centre, const Eigen::Matrix2d& covariance, const std::string& colour,
                 double opacity, bool filled);
  void cross(const Eigen::Vector2d& p, double size_px, const std::string& colour);
  void label(const Eigen::Vector2d& p, const std::string& text, const std::string& colour, double dx_px = 6,
             double dy_px = -6);
  /// The area the map shows (metres, its margin included).
  const Eigen::Vector2d& south_west() const { return min_; }
  const Eigen::Vector2d& north_east() const { return max_; }
  /// Finishes the map (scale bar, north arrow, frame) and returns the <svg> element.
  std::string finish() const;

 private:
  Eigen::Vector2d px(const Eigen::Vector2d& m) const;

  Eigen::Vector2d min_, max_;
  double scale_;  // px per metre
  double width_px_, height_px_;
  std::string title_;
  std::string body_;
  std::string under_;  ///< images, drawn first
};

/// Escapes text for HTML and SVG.
std::string escape_html(const std::string& text);

}  // namespace sarloc::app
