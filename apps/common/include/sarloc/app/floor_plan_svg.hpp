#pragma once
// A floor of a building drawn on an SvgMap: walls, doors and openings, flights, entries and the
// simulated world's furniture. The report draws each floor under the firefighters' tracks;
// `sarloc-eval plan` draws every floor of a plan alone, to check an imported one by eye.
#include <functional>
#include <string>

#include "sarloc/app/svg_map.hpp"
#include "sarloc/core/firefighter/floor_plan.hpp"

namespace sarloc::app {

/// Plan coordinates (m) to the map's frame.
using PlanToMap = std::function<Eigen::Vector2d(const firefighter::Vec2&)>;

void draw_floor(SvgMap& map, const firefighter::FloorPlan& plan, std::size_t floor, const PlanToMap& to_map);

/// Every floor of `plan`, one map each in plan metres, as one SVG document.
std::string floor_plan_svg(const firefighter::FloorPlan& plan);

}  // namespace sarloc::app
