#pragma once
// The avalanche deposit incident command plans the search over (issue 63): a simple polygon in
// the incident's ENU frame (east, north; metres). Made from a mission's or an operator's outline,
// checked at the door: at least 3 finite vertices, no crossing edges, a positive area. The
// outline may be given clockwise or not, closed or not.
//
//   const Deposit d(outline, "deposit");          // ConfigError naming "deposit" otherwise
//   d.contains(p); d.area_m2(); d.vertices();
#include <Eigen/Core>
#include <string>
#include <vector>

namespace sarloc::incident {

using Vec2 = Eigen::Vector2d;

class Deposit {
 public:
  /// `key` names the outline in errors (a mission key, a dashboard field).
  Deposit(std::vector<Vec2> outline, const std::string& key);

  /// Counter-clockwise, not closed (the last vertex is not the first again).
  const std::vector<Vec2>& vertices() const { return vertices_; }
  double area_m2() const { return area_m2_; }
  bool contains(const Vec2& p) const;  ///< inside or on the boundary

 private:
  std::vector<Vec2> vertices_;
  double area_m2_ = 0.0;
};

}  // namespace sarloc::incident
