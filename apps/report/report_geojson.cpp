#include "report_geojson.hpp"

#include "recorded_coverage.hpp"
#include "sarloc/app/incident_geojson.hpp"
#include "sarloc/core/common/errors.hpp"

namespace sarloc::report {

nlohmann::json render_geojson(const MissionRecord& r) {
  if (!r.incident_origin) {
    throw recording::RecordingError("no WGS-84 origin in '" + r.path +
                                    "' (no IncidentFrame sample, no mission file): nothing to place on the earth");
  }
  app::IncidentGeoJson picture;
  picture.epoch_ns = r.epoch_ns;
  if (r.deposit) picture.deposit = r.deposit->vertices();
  if (const auto coverage = recorded_coverage(r)) picture.strips = coverage->strips;
  for (const auto& [id, track] : r.responders) {
    app::GeoJsonTrack t{id, track.team, track.firefighter ? "firefighter" : "avalanche rescuer", {}};
    for (const auto& s : track.samples) t.points.push_back(s.position.position.head<2>());
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
