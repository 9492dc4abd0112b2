#include "sarloc/core/incident/strip_guidance.hpp"

#include <cmath>

#include "sarloc/core/common/angle.hpp"

namespace sarloc::incident {

std::optional<responder::Guidance> strip_guidance(const SearchPlanPicture& picture, const std::string& rescuer_id,
                                                  const responder::ResponderPosition& fix,
                                                  const StripGuidanceConfig& config) {
  const Vec2 here = fix.position.position.head<2>();
  if (!here.allFinite() || !std::isfinite(fix.heading_rad)) return std::nullopt;
  const auto& strips = picture.plan.strips;
  for (std::size_t i = 0; i < strips.size(); ++i) {
    const PlannedStrip& s = strips[i];
    if (s.done) continue;
    // Its rescuer walks it down from the top; a helper walks it up from the bottom.
    const bool walker = s.rescuer_id == rescuer_id, helper = !walker && s.helper_id == rescuer_id;
    if (!walker && !helper) continue;
    const auto& next_points = walker ? picture.next_points : picture.helper_next_points;
    if (i >= next_points.size() || !next_points[i] || !next_points[i]->allFinite()) return std::nullopt;
    const Vec2 target = *next_points[i];
    Vec2 way = target - here;
    const double distance = way.norm();
    if (distance < config.arrive_m) {
      const Vec2 start = walker ? s.strip.top : s.strip.bottom, end = walker ? s.strip.bottom : s.strip.top;
      const double length = (end - start).norm();
      if (length <= 0.0) return std::nullopt;
      way = (end - start) / length;
      if ((here - start).dot(way) >= length) return std::nullopt;  // past its far end
    }
    responder::Guidance g;
    g.rescuer_id = rescuer_id;
    g.signal_id = 0;
    g.stamp = fix.stamp;
    g.mode = responder::GuidanceMode::kPrimarySearch;
    g.heading_rad = std::atan2(way.y(), way.x());
    g.bearing_rad = wrap_angle(g.heading_rad - fix.heading_rad);
    g.distance_m = distance;
    g.uncertainty_radius_m = 0.0;
    g.step_m = config.step_m;
    return g;
  }
  return std::nullopt;
}

}  // namespace sarloc::incident
