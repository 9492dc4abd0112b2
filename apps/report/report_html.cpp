#include "report_html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "record_comparison.hpp"
#include "recorded_coverage.hpp"
#include "sarloc/app/floor_plan_svg.hpp"
#include "sarloc/app/svg_map.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"

namespace sarloc::report {

using app::escape_html;
using app::SvgMap;

namespace {

const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2"};

std::string colour_of(std::size_t index) { return kPalette[index % (sizeof kPalette / sizeof kPalette[0])]; }

std::string f(double v, int decimals = 1) {
  if (!std::isfinite(v)) return "—";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

std::string opt(const std::optional<double>& v) { return v ? f(*v) : "—"; }

Eigen::Vector2d xy(const Vec3& v) { return v.head<2>(); }

const char* state_text(incident::VictimState s) { return incident::to_string(s); }

std::string state_colour(incident::VictimState s) {
  switch (s) {
    case incident::VictimState::kFound: return "#2ca02c";
    case incident::VictimState::kLocated: return "#ff7f0e";
    default: return "#7f7f7f";
  }
}

struct Bounds {
  Eigen::Vector2d min = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d max = Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity());
  void add(const Eigen::Vector2d& p) {
    if (!p.allFinite()) return;
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  bool empty() const { return !(min.x() <= max.x()); }
};

// The nearest true victim to an estimate, and how far (the recording names no pairing).
std::pair<const TruthVictim*, double> nearest_truth(const MissionRecord& r, const Vec3& p) {
  const TruthVictim* best = nullptr;
  double distance = std::numeric_limits<double>::infinity();
  for (const auto& t : r.truth_victims) {
    const double d = (t.position - p).norm();
    if (d < distance) {
      distance = d;
      best = &t;
    }
  }
  return {best, distance};
}

// The basemap's tiles over the map, at the finest zoom that takes at most this many: about the
// map's own resolution (760 px wide), so that the report stays a few hundred kB.
constexpr std::size_t kReportBasemapTilesMax = 24;

// `tiles_drawn`: how many of the basemap's tiles lie under it.
std::string avalanche_map(const MissionRecord& r, const app::Basemap* basemap, std::size_t& tiles_drawn) {
  Bounds bounds;
  for (const auto& [id, track] : r.responders) {
    if (track.firefighter) continue;
    for (const auto& s : track.samples) bounds.add(xy(s.position.position));
  }
  for (const auto& [id, v] : r.victims) {
    if (!v.samples.empty()) bounds.add(xy(v.samples.back().position.position));
  }
  for (const auto& t : r.truth_victims) bounds.add(xy(t.position));
  if (bounds.empty()) return "";
  if (r.deposit) {
    for (const auto& p : r.deposit->vertices()) bounds.add(p);
  }
  SvgMap map(bounds.min, bounds.max, 760.0, 5.0, "Avalanche field (incident frame, m)");
  if (basemap != nullptr && r.incident_origin) {
    const incident::GeodeticFrame frame(*r.incident_origin);
    for (const auto& tile : basemap->tiles_over(frame, map.south_west(), map.north_east(), kReportBasemapTilesMax)) {
      if (const auto uri = app::tile_data_uri(*basemap, tile)) {
        map.image({tile.west, tile.north}, tile.width, tile.height, *uri);
        ++tiles_drawn;
      }
    }
  }
  if (r.deposit) map.polygon(r.deposit->vertices(), "#4a90c2", 0.12);  // under everything else
  std::size_t k = 0;
  for (const auto& [id, track] : r.responders) {
    if (track.firefighter) continue;
    std::vector<Eigen::Vector2d> points;
    for (const auto& s : track.samples) points.push_back(xy(s.position.position));
    map.polyline(points, colour_of(k), 2.0);
    if (!points.empty()) {
      map.dot(points.front(), 4, colour_of(k));
      map.label(points.back(), id, colour_of(k));
    }
    ++k;
  }
  for (const auto& [id, v] : r.victims) {
    // The estimate over time: a faint trail, 95 % ellipses when located, when found, and at the end.
    std::vector<Eigen::Vector2d> trail;
    for (const auto& s : v.samples) trail.push_back(xy(s.position.position));
    map.polyline(trail, "#555", 1.0, "2,3", 0.6);
    auto at = [&](std::optional<double> t) -> const VictimSample* {
      if (!t) return nullptr;
      for (const auto& s : v.samples) {
        if (s.t_s >= *t) return &s;
      }
      return nullptr;
    };
    for (const VictimSample* s : {at(v.located_s), at(v.found_s)}) {
      if (s != nullptr) map.ellipse95(xy(s->position.position), s->position.covariance.topLeftCorner<2, 2>(), state_colour(s->state), 0.5, false);
    }
    if (!v.samples.empty()) {
      const auto& last = v.samples.back();
      map.ellipse95(xy(last.position.position), last.position.covariance.topLeftCorner<2, 2>(), state_colour(last.state), 1.0, true);
      map.dot(xy(last.position.position), 3, state_colour(last.state));
      map.label(xy(last.position.position), "victim " + std::to_string(id), "#111", 8, 14);
    }
  }
  for (const auto& t : r.truth_victims) {
    map.cross(xy(t.position), 5, "#111");
    map.label(xy(t.position), "true " + t.name, "#111", 7, -7);
  }
  return map.finish();
}

std::vector<std::string> building_maps(const MissionRecord& r) {
  std::vector<std::string> maps;
  if (!r.building) {
    // Firefighters without a plan: their tracks on a blank map.
    bool any = false;
    for (const auto& [id, t] : r.responders) any = any || t.firefighter;
    if (!any) return maps;
  }
  const std::size_t floors = r.building ? r.building->plan.floors.size() : 1;
  for (std::size_t k = 0; k < floors; ++k) {
    Bounds bounds;
    if (r.building) {
      for (const auto& w : r.building->plan.floors[k].walls) {
        bounds.add(r.building->to_incident(w.a));
        bounds.add(r.building->to_incident(w.b));
      }
    }
    for (const auto& [id, track] : r.responders) {
      if (!track.firefighter) continue;
      for (const auto& s : track.samples) {
        if (static_cast<std::size_t>(s.floor) == k && s.source == responder::PositionSource::kMapAided) bounds.add(xy(s.position.position));
      }
    }
    if (bounds.empty()) continue;
    const std::string floor_name = r.building ? r.building->plan.floors[k].id : std::to_string(k);
    SvgMap map(bounds.min, bounds.max, 760.0, 1.5, "Building, floor " + std::to_string(k) + " (" + floor_name + ")");
    if (r.building) {
      app::draw_floor(map, r.building->plan, k, [&](const firefighter::Vec2& p) { return r.building->to_incident(p); });
    }
    std::size_t c = 0;
    for (const auto& [id, track] : r.responders) {
      if (!track.firefighter) continue;
      const std::string colour = colour_of(c++);
      std::vector<Eigen::Vector2d> aided, reckoned;
      double next_ellipse_s = -1e9;
      double next_flag_s = -1e9;
      for (const auto& s : track.samples) {
        if (static_cast<std::size_t>(s.floor) != k) continue;
        if (s.source == responder::PositionSource::kMapAided) {
          aided.push_back(xy(s.position.position));
          // Uncertainty every 30 mission seconds once converged (before, the cloud is the map).
          if (s.converged && s.t_s >= next_ellipse_s) {
            map.ellipse95(xy(s.position.position), s.position.covariance.topLeftCorner<2, 2>(), colour, 0.6, false);
            next_ellipse_s = s.t_s + 30.0;
          }
          if (s.map_error_suspected && s.t_s >= next_flag_s) {
            map.dot(xy(s.position.position), 3, "#d62728", 0.8);
            next_flag_s = s.t_s + 5.0;
          }
        } else if (s.source == responder::PositionSource::kDeadReckoning) {
          reckoned.push_back(xy(s.position.position));
        }
      }
      map.polyline(reckoned, colour, 1.0, "3,3", 0.5);
      map.polyline(aided, colour, 2.0);
      if (!aided.empty()) map.label(aided.back(), id, colour);
    }
    maps.push_back(map.finish());
  }
  return maps;
}

std::string timeline_svg(const MissionRecord& r) {
  static const std::vector<std::pair<std::string, std::string>> lanes = {
      {"victim", "#2ca02c"}, {"alarm", "#d62728"}, {"link", "#1f77b4"}, {"accountability", "#9467bd"},
      {"map error", "#ff7f0e"}, {"daemon", "#8c564b"}, {"command", "#17becf"}};
  const double width = 760.0, left = 110.0, lane_h = 22.0;
  const double end_s = std::max(1.0, r.duration_s);
  const double height = lane_h * static_cast<double>(lanes.size()) + 30.0;
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"timeline\" width=\"" + f(width) + "\" height=\"" + f(height) + "\">\n";
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    const double y = 10.0 + lane_h * static_cast<double>(i);
    svg += "<text x=\"4\" y=\"" + f(y + 14) + "\" font-size=\"12\">" + lanes[i].first + "</text>\n";
    svg += "<line x1=\"" + f(left) + "\" y1=\"" + f(y + 10) + "\" x2=\"" + f(width - 10) + "\" y2=\"" + f(y + 10) + "\" stroke=\"#ddd\"/>\n";
    for (const auto& e : r.events) {
      if (e.kind != lanes[i].first) continue;
      const double x = left + (width - 10 - left) * std::clamp(e.t_s / end_s, 0.0, 1.0);
      svg += "<rect x=\"" + f(x - 2) + "\" y=\"" + f(y + 2) + "\" width=\"4\" height=\"16\" fill=\"" + lanes[i].second +
             "\"><title>" + f(e.t_s) + " s: " + escape_html(e.text) + "</title></rect>\n";
    }
  }
  const double axis_y = 10.0 + lane_h * static_cast<double>(lanes.size()) + 12.0;
  for (int k = 0; k <= 5; ++k) {
    const double x = left + (width - 10 - left) * k / 5.0;
    svg += "<text x=\"" + f(x - 10) + "\" y=\"" + f(axis_y) + "\" font-size=\"11\">" + f(end_s * k / 5.0, 0) + " s</text>\n";
  }
  svg += "</svg>\n";
  return svg;
}

double track_length(const std::vector<PositionSample>& samples, responder::PositionSource source) {
  double length = 0.0;
  const PositionSample* last = nullptr;
  for (const auto& s : samples) {
    if (s.source != source) continue;
    if (last != nullptr) length += (xy(s.position.position) - xy(last->position.position)).norm();
    last = &s;
  }
  return length;
}

// The primary search as walked: how much of the deposit, and of each strip the planner would cut
// it into for these rescuers, their recorded tracks passed within hearing (half a strip) of.
// From incident command's last recorded plan: who it sent to each victim heard by several, and
// the dig order over the FOUND victims.
std::string plan_outcome(const MissionRecord& r) {
  if (!r.search_plan) return "";
  const auto& plan = *r.search_plan;
  std::string html;
  std::map<std::uint32_t, std::string> sent;
  for (const auto& h : plan.handed_over)
    if (h.victim_id != 0) sent[h.victim_id] = h.pursued_by;  // 0: a transmitter not yet placed
  if (!sent.empty()) {
    html += "<p>One rescuer per victim, at the end: ";
    std::string list;
    for (const auto& [victim, rescuer] : sent)
      list += (list.empty() ? "" : "; ") + std::string("victim ") + std::to_string(victim) +
              " sent: " + escape_html(rescuer);
    html += list + ".</p>\n";
  }
  if (plan.digs.digs.empty()) return html;
  html +=
      "<h3>Dig order at the end</h3>\n<p>Incident command's order over the FOUND victims (survival curve at "
      "each dig-out; expected survivors <b>" +
      f(plan.digs.expected_survivors, 2) +
      "</b>).</p>\n<table><tr><th>#</th><th>victim</th><th>depth (m)</th><th>buried (min)</th>"
      "<th>dug out in (min)</th><th>survival</th><th>digger</th></tr>\n";
  for (std::size_t i = 0; i < plan.digs.digs.size(); ++i) {
    const auto& d = plan.digs.digs[i];
    html += "<tr><td>" + std::to_string(i + 1) + "</td><td>" + std::to_string(d.victim_id) + "</td><td>" +
            f(d.depth_m, 1) + "</td><td>" + f(d.buried_min, 1) + "</td><td>" + f(d.done_min, 1) + "</td><td>" +
            f(100.0 * d.survival, 0) + " %</td><td>" +
            (d.digger_id.empty() ? std::string("none free") : escape_html(d.digger_id)) + "</td></tr>\n";
  }
  return html + "</table>\n";
}

std::string coverage_table(const MissionRecord& r) {
  const auto coverage = recorded_coverage(r);
  if (!coverage) return "";
  std::string html =
      "<p>The deposit: <b>" + f(100.0 * coverage->deposit_searched, 1) + " %</b> searched" +
      (coverage->from_plan
           ? std::string(", as incident command's last recorded search plan had it (its strips, and every cell a "
                         "rescuer's walk passed within half a strip's width of).")
           : std::string(" by the avalanche rescuers' recorded tracks (every cell a track passed within 20 m of, "
                         "half the default 40 m strip; the recording holds no search plan).")) +
      "</p>\n<table><tr><th>strip (from the left looking downhill)</th><th>width (m)</th><th>searched</th>" +
      (coverage->from_plan ? "<th>rescuer at the end</th>" : "") + "</tr>\n";
  for (std::size_t i = 0; i < coverage->strips.size(); ++i) {
    const auto& s = coverage->strips[i];
    html += "<tr><td>" + std::to_string(s.index) + "</td><td>" + f(s.width_m, 1) + "</td><td>" +
            f(100.0 * s.searched_fraction, 1) + " %</td>";
    if (coverage->from_plan)
      html +=
          "<td>" + (coverage->rescuers[i].empty() ? std::string("-") : escape_html(coverage->rescuers[i])) + "</td>";
    html += "</tr>\n";
  }
  return html + "</table>\n" + plan_outcome(r);
}

std::string victims_table(const MissionRecord& r) {
  std::string html =
      "<table><tr><th>victim</th><th>state</th><th>located (s)</th><th>found (s)</th><th>final 95 % radius (m)</th>"
      "<th>final position E, N, U (m)</th><th>WGS-84</th><th>nearest true victim</th><th>error "
      "(m)</th><th>sources</th></tr>\n";
  // Latitude and longitude for those who navigate by them (a helicopter, another team's GNSS).
  std::optional<incident::GeodeticFrame> frame;
  if (r.incident_origin) {
    try {
      frame.emplace(*r.incident_origin);
    } catch (const ConfigError&) {  // a recorded origin out of range: ENU only
    }
  }
  for (const auto& [id, v] : r.victims) {
    if (v.samples.empty()) continue;
    const auto& last = v.samples.back();
    const auto [truth, error] = nearest_truth(r, last.position.position);
    std::string sources;
    for (const auto& s : v.sources) sources += (sources.empty() ? "" : ", ") + s;
    html +=
        "<tr><td>" + std::to_string(id) + (v.evidence_conflict ? " <b class=\"warn\">conflict</b>" : "") +
        "</td><td style=\"color:" + state_colour(last.state) + "\">" + state_text(last.state) + "</td><td>" +
        opt(v.located_s) + "</td><td>" + opt(v.found_s) + "</td><td>" + f(radius95_2d(last.position.covariance), 2) +
        "</td><td>" + f(last.position.position.x()) + ", " + f(last.position.position.y()) + ", " +
        f(last.position.position.z()) + "</td><td>" +
        (frame && last.position.position.allFinite() ? incident::format_wgs84(frame->to_wgs84(last.position.position))
                                                     : "—") +
        "</td><td>" + (truth ? escape_html(truth->name) : "—") + "</td><td>" + (truth ? f(error, 2) : "—") +
        "</td><td>" + escape_html(sources) + "</td></tr>\n";
  }
  html += "</table>\n";
  // True victims never in the picture.
  for (const auto& t : r.truth_victims) {
    bool seen = false;
    for (const auto& [id, v] : r.victims) {
      if (!v.samples.empty() && (v.samples.back().position.position - t.position).norm() < 5.0) seen = true;
    }
    if (!seen) html += "<p class=\"warn\">True victim " + escape_html(t.name) + " has no estimate within 5 m in the picture.</p>\n";
  }
  return html;
}

std::string responders_table(const MissionRecord& r) {
  std::string html = "<table><tr><th>responder</th><th>team</th><th>role</th><th>positions</th><th>distance (m)</th>"
                     "<th>time inside (s)</th><th>converged (s)</th><th>last position source</th><th>RMSE vs truth (m)</th></tr>\n";
  for (const auto& [id, t] : r.responders) {
    if (t.samples.empty()) continue;
    const auto source = t.firefighter ? responder::PositionSource::kMapAided : responder::PositionSource::kGnss;
    std::optional<double> first, last, converged;
    for (const auto& s : t.samples) {
      if (s.source != responder::PositionSource::kMapAided) continue;
      if (!first) first = s.t_s;
      last = s.t_s;
      if (s.converged && !converged) converged = s.t_s;
    }
    static const char* const sources[] = {"GNSS", "map-aided", "dead reckoning", "manual"};
    html += "<tr><td>" + escape_html(id) + "</td><td>" + escape_html(t.team) + "</td><td>" +
            (t.firefighter ? "firefighter" : "avalanche rescuer") + "</td><td>" + std::to_string(t.samples.size()) + "</td><td>" +
            f(track_length(t.samples, source)) + "</td><td>" + (t.firefighter && first ? f(*last - *first) : "—") + "</td><td>" +
            opt(converged) + "</td><td>" + sources[static_cast<int>(t.samples.back().source) & 3] + "</td><td>" +
            (t.firefighter ? "not recorded" : "GNSS is the reference") + "</td></tr>\n";
  }
  return html + "</table>\n";
}

// Per team: its members, how far they went together, when it was first and last heard of.
std::string teams_table(const MissionRecord& r) {
  struct Team {
    std::vector<std::string> members;
    double distance_m = 0.0;
    std::optional<double> first_s, last_s;
  };
  std::map<std::string, Team> teams;
  for (const auto& [id, t] : r.responders) {
    auto& team = teams[t.team.empty() ? "(no team)" : t.team];
    team.members.push_back(id);
    const auto source = t.firefighter ? responder::PositionSource::kMapAided : responder::PositionSource::kGnss;
    team.distance_m += track_length(t.samples, source);
    if (!t.samples.empty()) {
      team.first_s = std::min(team.first_s.value_or(t.samples.front().t_s), t.samples.front().t_s);
      team.last_s = std::max(team.last_s.value_or(t.samples.back().t_s), t.samples.back().t_s);
    }
  }
  std::string html = "<table><tr><th>team</th><th>members</th><th>distance, all members (m)</th><th>first heard (s)</th>"
                     "<th>last heard (s)</th></tr>\n";
  for (const auto& [name, team] : teams) {
    std::string members;
    for (const auto& m : team.members) members += (members.empty() ? "" : ", ") + m;
    html += "<tr><td>" + escape_html(name) + "</td><td>" + escape_html(members) + "</td><td>" + f(team.distance_m) +
            "</td><td>" + opt(team.first_s) + "</td><td>" + opt(team.last_s) + "</td></tr>\n";
  }
  return html + "</table>\n";
}

std::string quality_table(const MissionRecord& r) {
  std::string html = "<table><tr><th>topic</th><th>in the file</th><th>undecodable</th><th>received by the recorder</th>"
                     "<th>written</th><th>lost (DDS)</th><th>rejected</th></tr>\n";
  for (const auto& [topic, q] : r.quality) {
    std::string rejected;
    for (const auto& [reason, n] : q.rejected) rejected += (rejected.empty() ? "" : ", ") + reason + " " + std::to_string(n);
    const bool bad = q.undecodable > 0 || q.lost > 0 || !rejected.empty();
    html += std::string("<tr") + (bad ? " class=\"warn\"" : "") + "><td>" + escape_html(topic) + "</td><td>" +
            std::to_string(q.recorded) + "</td><td>" + std::to_string(q.undecodable) + "</td><td>" + std::to_string(q.received) +
            "</td><td>" + std::to_string(q.written) + "</td><td>" + std::to_string(q.lost) + "</td><td>" +
            (rejected.empty() ? "0" : escape_html(rejected)) + "</td></tr>\n";
  }
  html += "</table>\n";
  bool any = false;
  std::string nodes = "<table><tr><th>node</th><th>samples it rejected, by reason</th></tr>\n";
  for (const auto& [node, reasons] : r.node_rejects) {
    if (reasons.empty()) continue;
    any = true;
    std::string text;
    for (const auto& [reason, n] : reasons) text += (text.empty() ? "" : ", ") + reason + " " + std::to_string(n);
    nodes += "<tr><td>" + escape_html(node) + "</td><td>" + escape_html(text) + "</td></tr>\n";
  }
  html += any ? "<h3>Samples the nodes rejected</h3>\n" + nodes + "</table>\n" : "<p>No node rejected a sample.</p>\n";
  return html;
}

std::string comparison(const MissionRecord& r, const MissionRecord& base) {
  const RecordComparison c = compare_records(r, base);
  const auto failures = reproduction_failures(c);
  std::string html = "<section id=\"comparison\"><h2>Difference from " + escape_html(base.path) + "</h2>\n";
  html += failures.empty()
              ? "<p><b>Reproduces it</b>: the same victims found, each within 0.5 m and 5 s, and every map-aided track "
                "within 0.5 m RMS.</p>\n"
              : "<div class=\"banner\"><b>Does not reproduce it:</b><ul>";
  for (const auto& failure : failures) html += "<li>" + escape_html(failure) + "</li>";
  if (!failures.empty()) html += "</ul></div>\n";
  html += "<p>Victims are paired by the nearest final estimate.</p>\n<table><tr><th>victim here</th><th>there</th>"
          "<th>state here / there</th><th>found here / there (s)</th><th>distance between final estimates (m)</th>"
          "<th>95 % radius here / there (m)</th></tr>\n";
  for (const auto& p : c.victims) {
    const bool apart = p.there == 0 || p.distance_m > p.radius_here_m + p.radius_there_m;
    html += std::string("<tr") + (apart ? " class=\"warn\"" : "") + "><td>" + std::to_string(p.here) + "</td><td>" +
            (p.there == 0 ? "none" : std::to_string(p.there)) + "</td><td>" + state_text(p.state_here) + " / " +
            (p.there == 0 ? "—" : state_text(p.state_there)) + "</td><td>" + opt(p.found_here_s) + " / " + opt(p.found_there_s) +
            "</td><td>" + (p.there == 0 ? "—" : f(p.distance_m, 2)) + "</td><td>" + f(p.radius_here_m, 2) + " / " +
            (p.there == 0 ? "—" : f(p.radius_there_m, 2)) + "</td></tr>\n";
  }
  html += "</table>\n";
  if (!c.tracks.empty()) {
    html += "<table><tr><th>responder</th><th>map-aided fixes at the same stamp</th><th>RMS difference (m)</th>"
            "<th>largest (m)</th></tr>\n";
    for (const auto& t : c.tracks) {
      html += "<tr><td>" + escape_html(t.responder) + "</td><td>" + std::to_string(t.matched) + "</td><td>" + f(t.rms_m, 2) +
              "</td><td>" + f(t.max_m, 2) + "</td></tr>\n";
    }
    html += "</table>\n";
  }
  return html + "</section>\n";
}

}  // namespace

std::string render_report(const MissionRecord& r, const MissionRecord* baseline, const app::Basemap* basemap) {
  std::size_t found = 0, located = 0;
  for (const auto& [id, v] : r.victims) {
    if (v.samples.empty()) continue;
    if (v.samples.back().state == incident::VictimState::kFound) ++found;
    else if (v.samples.back().state == incident::VictimState::kLocated) ++located;
  }
  std::size_t alarms = 0;
  for (const auto& e : r.events) alarms += e.kind == "alarm" && e.text.size() > 6 && e.text.substr(e.text.size() - 6) == "raised";
  const auto md = [&](const std::string& key) {
    const auto it = r.recording_metadata.find(key);
    return it == r.recording_metadata.end() ? std::string("—") : it->second;
  };

  std::string html = R"(<!doctype html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width">
<title>sarloc mission report</title>
<style>
body { font-family: sans-serif; margin: 1.5em auto; max-width: 1100px; color: #111; }
h1 { margin-bottom: 0.2em; } h2 { border-bottom: 2px solid #ccd; padding-bottom: 2px; margin-top: 1.6em; }
table { border-collapse: collapse; margin: 0.5em 0; font-size: 13px; }
th, td { border: 1px solid #ccd; padding: 3px 7px; text-align: left; }
th { background: #eef1f5; }
.warn { color: #b00; }
tr.warn td { background: #fff1f0; }
.banner { background: #fff1f0; border: 2px solid #b00; padding: 0.6em; margin: 1em 0; }
.figures { display: flex; gap: 1.5em; flex-wrap: wrap; }
.figure { background: #eef1f5; padding: 0.5em 1em; border-radius: 4px; }
.figure b { font-size: 22px; display: block; }
svg { display: block; margin: 0.5em 0; }
.legend { font-size: 12px; color: #333; }
</style></head><body>
)";
  html += "<h1>Mission report: " + escape_html(r.mission_name) + "</h1>\n";
  html += "<p>Recording <code>" + escape_html(r.path) + "</code>; " + escape_html(md("software")) + "; " +
          f(r.duration_s) + " mission s (speedup " + f(r.speedup, 1) + "); " + std::to_string(r.read.messages) + " messages.</p>\n";
  if (!r.read.damage.empty()) {
    html += "<div class=\"banner\"><b>This recording is damaged.</b> The report shows everything before the damage (" +
            std::to_string(r.read.good_bytes) + " of " + std::to_string(r.read.file_size) + " bytes). What could not be read: " +
            escape_html(r.read.damage) + ". <code>sarloc-record --recover</code> rewrites it.</div>\n";
  }
  html += "<div class=\"figures\"><div class=\"figure\"><b>" + std::to_string(found) + "</b>victims found</div>" +
          "<div class=\"figure\"><b>" + std::to_string(located) + "</b>located, not yet found</div>" +
          "<div class=\"figure\"><b>" + std::to_string(r.truth_victims.size()) + "</b>true victims (simulation)</div>" +
          "<div class=\"figure\"><b>" + std::to_string(r.responders.size()) + "</b>responders</div>" +
          "<div class=\"figure\"><b>" + std::to_string(alarms) + "</b>alarms raised</div></div>\n";

  html += "<section id=\"maps\"><h2>Maps</h2>\n";
  std::size_t tiles = 0;
  const std::string field = avalanche_map(r, basemap, tiles);
  if (!field.empty()) {
    const std::string under =
        basemap == nullptr   ? ""
        : !r.incident_origin ? " No basemap: the recording holds no WGS-84 origin of the incident to place it by."
        : tiles == 0         ? " No basemap: the <code>--basemap</code> file has no tile over this field."
                     : " Under it: the offline basemap (<code>--basemap</code>), its tiles placed by the incident's "
                       "WGS-84 origin.";
    html += field +
            "<p class=\"legend\">Lines: rescuers' tracks (dot: start). Dashed grey: each victim's estimate over time; "
            "ellipses: 95 % when located, when found (thin) and at the end (filled), green found, orange located, grey "
            "unconfirmed. Black crosses: true positions (simulation). Pale blue area: the avalanche deposit "
            "(the mission's incident.deposit)." +
            under + "</p>\n";
  }
  for (const auto& map : building_maps(r)) {
    html += map +
            "<p class=\"legend\">Walls black, doors green, openings blue, flights orange, entries red, furniture grey. "
            "Solid: map-aided track, with its 95 % ellipse every 30 s "
            "once converged; dashed: the device's own dead reckoning; red dots: map error suspected (at most one per "
            "5 s).</p>\n";
  }
  html += "</section>\n";

  html += "<section id=\"timeline\"><h2>Timeline</h2>\n" + timeline_svg(r) +
          "<table><tr><th>mission s</th><th>what</th><th>event</th></tr>\n";
  for (const auto& e : r.events) {
    html += "<tr><td>" + f(e.t_s) + "</td><td>" + escape_html(e.kind) + "</td><td>" + escape_html(e.text) + "</td></tr>\n";
  }
  html += "</table></section>\n";
  html += "<section id=\"victims\"><h2>Victims</h2>\n" + victims_table(r) + "</section>\n";
  if (r.deposit || r.search_plan)
    html += "<section id=\"coverage\"><h2>Search coverage</h2>\n" + coverage_table(r) + "</section>\n";
  html += "<section id=\"responders\"><h2>Teams and responders</h2>\n" + teams_table(r) + responders_table(r) + "</section>\n";
  html += "<section id=\"quality\"><h2>Data quality</h2>\n" + quality_table(r) + "</section>\n";
  if (baseline != nullptr) html += comparison(r, *baseline);
  if (!r.notes.empty()) {
    html += "<section id=\"notes\"><h2>Notes</h2><ul>\n";
    for (const auto& n : r.notes) html += "<li>" + escape_html(n) + "</li>\n";
    html += "</ul></section>\n";
  }
  html += "</body></html>\n";
  return html;
}

}  // namespace sarloc::report
