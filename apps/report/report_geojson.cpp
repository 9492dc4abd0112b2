#include "report_geojson.hpp"

#include "sarloc/app/incident_geojson.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/search_coverage.hpp"
#include "sarloc/core/incident/search_strips.hpp"

namespace sarloc::report {
namespace {

Eigen::Vector2d xy(const Vec3& p) { return p.head<2>(); }

// The strips over the deposit, entered from where the avalanche rescuers started (the planner's
// rule without a fall line), and how much of each their recorded walks covered.
std::vector<app::GeoJsonStrip> covered_strips(const MissionRecord& r) {
  const incident::Deposit& deposit = *r.deposit;
  Eigen::Vector2d entry = Eigen::Vector2d::Zero();
  std::size_t starts = 0;
  for (const auto& [id, track] : r.responders) {
    if (track.firefighter || track.samples.empty() || !track.samples.front().position.position.allFinite()) continue;
    entry += xy(track.samples.front().position.position);
    ++starts;
  }
  if (starts == 0) {
    for (const auto& v : deposit.vertices()) entry += v;
    starts = deposit.vertices().size();
  }
  const incident::StripPlanConfig config;
  const auto strips = incident::plan_strips(deposit, config, entry / static_cast<double>(starts));
  incident::SearchCoverage coverage(deposit, strips, 1.0);
  for (const auto& [id, track] : r.responders) {
    if (track.firefighter) continue;
    for (std::size_t k = 1; k < track.samples.size(); ++k) {
      const Vec3& a = track.samples[k - 1].position.position;
      const Vec3& b = track.samples[k].position.position;
      if (a.allFinite() && b.allFinite()) coverage.add_walk(xy(a), xy(b), 0.5 * config.strip_width_m);
    }
  }
  std::vector<app::GeoJsonStrip> out;
  for (const auto& s : strips) out.push_back({s.index, s.outline, s.width_m, coverage.searched(s.index)});
  return out;
}

}  // namespace

nlohmann::json render_geojson(const MissionRecord& r) {
  if (!r.incident_origin) {
    throw recording::RecordingError("no WGS-84 origin in '" + r.path +
                                    "' (no IncidentFrame sample, no mission file): nothing to place on the earth");
  }
  app::IncidentGeoJson picture;
  picture.epoch_ns = r.epoch_ns;
  if (r.deposit) {
    picture.deposit = r.deposit->vertices();
    picture.strips = covered_strips(r);
  }
  for (const auto& [id, track] : r.responders) {
    app::GeoJsonTrack t{id, track.team, track.firefighter ? "firefighter" : "avalanche rescuer", {}};
    for (const auto& s : track.samples) t.points.push_back(xy(s.position.position));
    picture.tracks.push_back(std::move(t));
  }
  for (const auto& [id, v] : r.victims) {
    if (v.samples.empty()) continue;
    const auto& last = v.samples.back();
    picture.victims.push_back(
        {id, incident::to_string(last.state), last.position, v.located_s, v.found_s, v.sources, v.evidence_conflict});
  }
  try {
    return app::to_geojson(picture, incident::GeodeticFrame(*r.incident_origin));
  } catch (const ConfigError& error) {  // a recorded origin out of range
    throw recording::RecordingError("the recorded WGS-84 origin of '" + r.path + "' is unusable: " + error.what());
  }
}

}  // namespace sarloc::report
