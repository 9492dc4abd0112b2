#include "sarloc/app/floor_plan_svg.hpp"

#include <algorithm>
#include <cmath>

namespace sarloc::app {

using firefighter::Vec2;

void draw_floor(SvgMap& map, const firefighter::FloorPlan& plan, std::size_t floor, const PlanToMap& to_map) {
  const firefighter::Floor& f = plan.floors.at(floor);
  for (const auto& item : f.furniture) {
    map.polygon({to_map(item.min), to_map({item.max.x(), item.min.y()}), to_map(item.max),
                 to_map({item.min.x(), item.max.y()})},
                "#bbbbbb", 0.4);
  }
  for (const auto& stairs : plan.stairs_of(floor)) {
    const Vec2 along = stairs->top - stairs->bottom;
    const Vec2 side = Vec2(-along.y(), along.x()).normalized() * (0.5 * stairs->width_m);
    map.polygon({to_map(stairs->bottom - side), to_map(stairs->bottom + side), to_map(stairs->top + side),
                 to_map(stairs->top - side)},
                "#e0a040", 0.35);
    map.line(to_map(stairs->bottom), to_map(stairs->top), "#e0a040", 1.5);  // the way up
    map.label(to_map(stairs->top), stairs->id + " (up to " + stairs->upper_floor + ")", "#a06010");
  }
  for (const auto& w : f.walls) map.line(to_map(w.a), to_map(w.b), "#333", 3.0);
  for (const auto& d : f.doors) {
    // The opening itself, drawn over its wall in the background colour, with a thin marker.
    const auto wall = std::find_if(f.walls.begin(), f.walls.end(), [&](const auto& w) { return w.id == d.wall; });
    if (wall == f.walls.end()) continue;
    const Vec2 along = (wall->b - wall->a).normalized() * (0.5 * d.width_m);
    map.line(to_map(d.center - along), to_map(d.center + along), "#f7f9fb", 4.0);
    map.line(to_map(d.center - along), to_map(d.center + along),
             d.kind == firefighter::OpeningKind::kDoor ? "#8fbc8f" : "#87ceeb", 1.0);
  }
  for (const auto& e : plan.entries) {
    if (e.floor != f.id) continue;
    const Vec2 ahead = e.position + Vec2(std::cos(e.heading_rad), std::sin(e.heading_rad));
    map.line(to_map(e.position), to_map(ahead), "#d62728", 2.0);
    map.dot(to_map(e.position), 4, "#d62728");
    map.label(to_map(e.position), "entry " + e.id, "#d62728");
  }
}

std::string floor_plan_svg(const firefighter::FloorPlan& plan) {
  Vec2 min, max;
  plan.bounds(min, max);
  std::string svg;
  for (std::size_t k = 0; k < plan.floors.size(); ++k) {
    SvgMap map(min, max, 760.0, 1.5,
               plan.name + ", floor " + plan.floors[k].id + " (" +
                   std::to_string(plan.floors[k].elevation_m).substr(0, 4) + " m; plan m)");
    draw_floor(map, plan, k, [](const Vec2& p) { return p; });
    svg += map.finish();
  }
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<html xmlns=\"http://www.w3.org/1999/xhtml\"><body>\n" + svg +
         "</body></html>\n";
}

}  // namespace sarloc::app
