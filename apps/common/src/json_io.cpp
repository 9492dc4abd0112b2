#include "sarloc/app/json_io.hpp"

#include <fstream>
#include <stdexcept>

namespace sarloc::app {
namespace {

template <typename T>
nlohmann::json optional_json(const std::optional<T>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

responder::EstimatorStatus status_from_name(const std::string& name) {
  for (int i = 0; i <= static_cast<int>(responder::EstimatorStatus::kFound); ++i) {
    const auto s = static_cast<responder::EstimatorStatus>(i);
    if (name == status_name(s)) return s;
  }
  throw std::runtime_error("signals[].status = '" + name + "': not an estimator status");
}

nlohmann::json picture_json(const std::vector<mission::PictureVictimOutcome>& picture) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& f : picture) {
    out.push_back({{"victim_id", f.victim_id},
                   {"position", to_json(f.position)},
                   {"confirmed", f.confirmed},
                   {"found", f.found},
                   {"dug_out", f.dug_out},
                   {"sources", f.source_names.size()},
                   {"source_names", f.source_names},
                   {"possibly_same_as", f.possibly_same_as},
                   {"radius95_m", f.radius95_m},
                   {"matches_a_buried_victim", f.matches_a_buried_victim},
                   {"evidence_conflict", f.evidence_conflict},
                   {"located_at_s", optional_json(f.located_at_s)},
                   {"found_at_s", optional_json(f.found_at_s)}});
  }
  return out;
}

}  // namespace

const char* status_name(responder::EstimatorStatus status) {
  switch (status) {
    case responder::EstimatorStatus::kInitialising: return "INITIALISING";
    case responder::EstimatorStatus::kMultimodal: return "MULTIMODAL";
    case responder::EstimatorStatus::kConverged: return "CONVERGED";
    case responder::EstimatorStatus::kLocated: return "LOCATED";
    case responder::EstimatorStatus::kFound: return "FOUND";
  }
  return "?";
}

nlohmann::json to_json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json to_json(const incident::FusedVictim& v) {
  return {{"victim_id", v.victim_id},
          {"position", to_json(v.position.position)},
          {"floor", v.floor},
          {"state", static_cast<int>(v.state)},
          {"sources", v.sources.size()},
          {"evidence_conflict", v.evidence_conflict}};
}

nlohmann::json to_json(const std::vector<incident::TeamStatus>& teams) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& t : teams) {
    for (const auto& m : t.members) {
      rows.push_back({{"team_id", t.team_id},
                      {"responder_id", m.responder_id},
                      {"link", static_cast<int>(m.link)},
                      {"accountability", static_cast<int>(m.accountability)}});
    }
  }
  return rows;
}

nlohmann::json to_json(const mission::DeviceSummary& d) {
  nlohmann::json j;
  j["rescuer_id"] = d.rescuer_id;
  j["epochs"] = d.epochs;
  j["distance_walked_m"] = d.distance_walked_m;
  j["fallbacks"] = d.fallbacks;
  j["guidance_switches"] = d.guidance_switches;
  j["guided_by"] = d.guided_by;
  j["daemon_after_fallback"] = d.daemon_after_fallback;
  j["latency_ms"] = {{"samples", d.latency_samples}};
  if (d.latency_p50_ms) j["latency_ms"]["p50"] = *d.latency_p50_ms;
  if (d.latency_p99_ms) j["latency_ms"]["p99"] = *d.latency_p99_ms;
  nlohmann::json signals = nlohmann::json::array();
  for (const auto& s : d.signals) {
    nlohmann::json e{{"signal_id", s.signal_id}, {"status", status_name(s.status)}};
    if (s.victim_index) e["victim_index"] = *s.victim_index;
    if (s.relative_error_m) e["relative_error_m"] = *s.relative_error_m;
    if (s.radius95_m) e["radius95_m"] = *s.radius95_m;
    signals.push_back(e);
  }
  j["signals"] = signals;
  if (d.gnss_error_m) j["gnss_error_m"] = *d.gnss_error_m;
  return j;
}

nlohmann::json to_json(const mission::FirefighterDeviceSummary& f) {
  nlohmann::json j;
  j["responder_id"] = f.responder_id;
  j["team"] = f.team;
  j["role"] = "firefighter";
  j["enter_at_s"] = f.enter_at_s;
  j["fixes"] = f.fixes;
  if (f.converged_at_s) j["converged_at_s"] = *f.converged_at_s;
  if (f.time_to_converge_s) j["time_to_converge_s"] = *f.time_to_converge_s;
  if (f.rmse_after_convergence_m) j["rmse_after_convergence_m"] = *f.rmse_after_convergence_m;
  j["wrong_floor"] = f.wrong_floor;
  j["map_error_share"] = f.map_error_share;
  j["confirmed_share"] = f.confirmed_share;
  j["confirmed_outside_99"] = f.confirmed_outside_99;
  j["distance_walked_m"] = f.distance_walked_m;
  j["dead_reckoning_s"] = f.dead_reckoning_s;
  j["own_positions"] = f.own_positions;
  if (f.own_max_error_m) j["own_max_error_m"] = *f.own_max_error_m;
  j["own_outside_99"] = f.own_outside_99;
  j["floors_visited"] = f.floors_visited;
  j["floors_reported"] = f.floors_reported;
  nlohmann::json alarms = nlohmann::json::array();
  for (const auto& a : f.alarms) {
    nlohmann::json e{{"kind", a.kind}, {"raised_s", a.raised_s}};
    if (a.cleared_s) e["cleared_s"] = *a.cleared_s;
    if (a.true_event_s) e["true_event_s"] = *a.true_event_s;
    if (a.delay_s) e["delay_s"] = *a.delay_s;
    if (a.clear_delay_s) e["clear_delay_s"] = *a.clear_delay_s;
    alarms.push_back(e);
  }
  j["alarms"] = alarms;
  return j;
}

mission::FirefighterDeviceSummary firefighter_summary_from_json(const nlohmann::json& j) {
  try {
    mission::FirefighterDeviceSummary f;
    f.responder_id = j.at("responder_id").get<std::string>();
    f.team = j.value("team", std::string{});
    f.enter_at_s = j.value("enter_at_s", 0.0);
    f.fixes = j.value("fixes", std::size_t{0});
    if (j.contains("converged_at_s")) f.converged_at_s = j.at("converged_at_s").get<double>();
    if (j.contains("time_to_converge_s")) f.time_to_converge_s = j.at("time_to_converge_s").get<double>();
    if (j.contains("rmse_after_convergence_m")) f.rmse_after_convergence_m = j.at("rmse_after_convergence_m").get<double>();
    f.wrong_floor = j.value("wrong_floor", std::size_t{0});
    f.map_error_share = j.value("map_error_share", 0.0);
    f.confirmed_share = j.value("confirmed_share", 0.0);
    f.confirmed_outside_99 = j.value("confirmed_outside_99", std::size_t{0});
    f.distance_walked_m = j.value("distance_walked_m", 0.0);
    f.dead_reckoning_s = j.value("dead_reckoning_s", 0.0);
    f.own_positions = j.value("own_positions", std::size_t{0});
    if (j.contains("own_max_error_m")) f.own_max_error_m = j.at("own_max_error_m").get<double>();
    f.own_outside_99 = j.value("own_outside_99", std::size_t{0});
    f.floors_visited = j.value("floors_visited", std::vector<std::int32_t>{});
    f.floors_reported = j.value("floors_reported", std::vector<std::int32_t>{});
    for (const auto& e : j.value("alarms", nlohmann::json::array())) {
      mission::FirefighterAlarmRecord a;
      a.kind = e.at("kind").get<std::string>();
      a.raised_s = e.at("raised_s").get<double>();
      if (e.contains("cleared_s")) a.cleared_s = e.at("cleared_s").get<double>();
      if (e.contains("true_event_s")) a.true_event_s = e.at("true_event_s").get<double>();
      if (e.contains("delay_s")) a.delay_s = e.at("delay_s").get<double>();
      if (e.contains("clear_delay_s")) a.clear_delay_s = e.at("clear_delay_s").get<double>();
      f.alarms.push_back(a);
    }
    return f;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("firefighter summary: ") + e.what());
  }
}

mission::DeviceSummary device_summary_from_json(const nlohmann::json& j) {
  try {
    mission::DeviceSummary d;
    d.rescuer_id = j.at("rescuer_id").get<std::string>();
    d.epochs = j.value("epochs", std::size_t{0});
    d.distance_walked_m = j.value("distance_walked_m", 0.0);
    d.fallbacks = j.value("fallbacks", 0);
    d.guidance_switches = j.value("guidance_switches", 0);
    d.guided_by = j.value("guided_by", std::map<std::string, std::size_t>{});
    d.daemon_after_fallback = j.value("daemon_after_fallback", std::size_t{0});
    if (const auto it = j.find("latency_ms"); it != j.end()) {
      d.latency_samples = it->value("samples", std::size_t{0});
      if (it->contains("p50")) d.latency_p50_ms = it->at("p50").get<double>();
      if (it->contains("p99")) d.latency_p99_ms = it->at("p99").get<double>();
    }
    for (const auto& s : j.value("signals", nlohmann::json::array())) {
      mission::DeviceSignal signal;
      signal.signal_id = s.at("signal_id").get<std::uint32_t>();
      signal.status = status_from_name(s.at("status").get<std::string>());
      if (s.contains("victim_index")) signal.victim_index = s.at("victim_index").get<std::size_t>();
      if (s.contains("relative_error_m")) signal.relative_error_m = s.at("relative_error_m").get<double>();
      if (s.contains("radius95_m")) signal.radius95_m = s.at("radius95_m").get<double>();
      d.signals.push_back(signal);
    }
    if (j.contains("gnss_error_m")) d.gnss_error_m = j.at("gnss_error_m").get<double>();
    return d;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("device summary: ") + e.what());
  }
}

nlohmann::json to_json(const mission::MissionSummary& s) {
  nlohmann::json out;
  out["mission"] = s.mission;
  out["true_victim_count"] = s.victims.size();
  out["fused_victim_count"] = s.fused_victims.size();
  out["victims"] = nlohmann::json::array();
  for (const auto& v : s.victims) {
    nlohmann::json j{{"name", v.name}, {"true_position", to_json(v.true_position)}};
    if (v.victim_id) {
      j["victim_id"] = *v.victim_id;
      j["estimate"] = to_json(*v.estimate);
      j["sources"] = v.sources;
    }
    j["error_m"] = optional_json(v.error_m);
    j["time_to_locate_s"] = optional_json(v.time_to_locate_s);
    j["found"] = v.found;
    j["found_at_s"] = optional_json(v.found_at_s);
    j["dug_out_min"] = optional_json(v.dug_out_min);
    j["survival"] = optional_json(v.survival);
    j["relative_error_m"] = optional_json(v.relative_error_m);
    j["false_found"] = v.false_found;
    j["found_by_finder"] = v.found_by_finder();
    j["finders"] = v.finders;
    out["victims"].push_back(j);
  }
  out["all_found"] = s.all_found;
  out["expected_survivors"] = optional_json(s.expected_survivors);
  out["unfound_count"] = s.unfound_count;
  out["unfound_survival_at_most"] = s.unfound_survival_at_most;
  out["found_by_finder_count"] = s.found_by_finder_count();
  out["command_alive_at_end"] = s.command_alive_at_end;
  out["picture_available"] = s.picture_available;
  out["fused_victims"] = picture_json(s.fused_victims);
  out["confirmed_fused_victim_count"] = s.confirmed_fused_victim_count();
  out["mission_s"] = s.mission_s;
  out["wall_s"] = s.wall_s;
  out["rescuers"] = nlohmann::json::array();
  for (const auto& id : s.rescuer_ids) {
    nlohmann::json entry{{"id", id}};
    if (const auto it = s.devices.find(id); it != s.devices.end()) {
      const auto& d = it->second;
      const auto device = to_json(d);
      entry["distance_walked_m"] = d.distance_walked_m;
      entry["fallbacks"] = d.fallbacks;
      entry["guidance_switches"] = d.guidance_switches;
      entry["latency_ms"] = device["latency_ms"];
      entry["gnss_error_m"] = d.gnss_error_m.value_or(-1.0);
      entry["guided_by"] = d.guided_by;
      entry["daemon_after_fallback"] = d.daemon_after_fallback;
    }
    out["rescuers"].push_back(entry);
  }
  out["faults"] = nlohmann::json::array();
  for (const auto& f : s.faults) {
    nlohmann::json fj{{"action", f.action}, {"target", f.target}, {"at_s", f.at_s}, {"done", f.done}};
    if (f.link_lost_after_s) fj["link_lost_after_s"] = *f.link_lost_after_s;
    if (f.handover_after_s) fj["handover_after_s"] = *f.handover_after_s;
    if (!f.taken_over_by.empty()) fj["taken_over_by"] = f.taken_over_by;
    if (f.action == "kill" && f.target == "command") fj["picture_at_kill"] = picture_json(f.picture_at_kill);
    out["faults"].push_back(fj);
  }
  if (!s.firefighters.empty() || !s.firefighters_without_summary.empty()) {
    out["firefighters"] = nlohmann::json::array();
    for (const auto& f : s.firefighters) out["firefighters"].push_back(to_json(f));
    out["firefighters_without_summary"] = s.firefighters_without_summary;
  }
  out["alarms"] = nlohmann::json::array();
  for (const auto& a : s.picture_alarms) {
    nlohmann::json aj{{"alarm_id", a.alarm_id}, {"kind", a.kind}, {"responder_id", a.responder_id}, {"raised_s", a.raised_s}};
    if (a.cleared_s) aj["cleared_s"] = *a.cleared_s;
    out["alarms"].push_back(aj);
  }
  out["links_at_end"] = s.links_at_end;
  return out;
}

void write_json_file(const std::string& path, const nlohmann::json& j) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot open " + path + " for writing");
  out << j.dump(2) << "\n";
  out.flush();
  if (!out) throw std::runtime_error("writing " + path + " failed (disk full?)");
}

}  // namespace sarloc::app
