#include "sarloc/app/mission_config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "sarloc/app/avalanche_yaml.hpp"
#include "sarloc/app/firefighter_yaml.hpp"
#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/app/yaml_reader.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/identifier.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"

namespace sarloc::app {
namespace {

// Ids name files, partitions and page elements: the one identifier rule, at load.
void require_identifier(const std::string& value, const std::string& where, bool empty_allowed = false) {
  if (auto problem = identifier_problem(value, where, empty_allowed); !problem.empty()) throw ConfigError(problem);
}

// An outline in WGS-84 (a list of {latitude_deg, longitude_deg}), into the incident frame about
// the incident's origin: the deposit's, a sector's area.
std::vector<incident::Vec2> read_outline(YamlReader& r, const std::string& key, const GeodeticOrigin& origin,
                                         const std::string& file) {
  const incident::GeodeticFrame frame(origin);
  std::vector<incident::Vec2> outline;
  for (auto& vertex : r.child_list(key)) {
    incident::Geodetic g;
    g.altitude_m = origin.altitude_m;
    vertex.require("latitude_deg", g.latitude_deg);
    vertex.require("longitude_deg", g.longitude_deg);
    vertex.expect_done();
    try {
      outline.push_back(frame.to_enu(g).head<2>());
    } catch (const InputError& e) {
      throw ConfigError(file + ": " + vertex.path() + ": " + e.what());
    }
  }
  return outline;
}

std::string resolve(const std::string& path, const std::string& base_dir) {
  if (path.empty() || std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(base_dir) / path).lexically_normal().string();
}

void read_fusion(YamlReader r, incident::VictimFusionConfig& c) {
  r.read("gate_probability", c.gate_probability);
  r.read("keep_gate_probability", c.keep_gate_probability);
  r.read("merge_gate_probability", c.merge_gate_probability);
  r.read("source_timeout_s", c.source_timeout_s);
  r.read("located_radius_m", c.located_radius_m);
  r.read("confirm_requires_device", c.confirm_requires_device);
  r.read("dug_out_grace_s", c.dug_out_grace_s);
  std::string weighting = c.weighting == incident::CiWeighting::kInverseTrace ? "inverse_trace" : "min_trace";
  r.read("weighting", weighting);
  if (weighting == "inverse_trace") {
    c.weighting = incident::CiWeighting::kInverseTrace;
  } else if (weighting == "min_trace") {
    c.weighting = incident::CiWeighting::kMinTrace;
  } else {
    throw ConfigError(r.source() + ": " + r.path() + ".weighting = '" + weighting +
                      "': expected inverse_trace or min_trace");
  }
  r.expect_done();
}

}  // namespace

std::vector<std::string> MissionConfig::partitions_of_sector(const std::string& sector) {
  if (sector.empty()) return {};
  return {"sector-" + sector};
}

void MissionConfig::validate() const {
  require(time_limit_s > 0.0 && time_limit_s <= 24 * 3600.0, "mission.time_limit_s", time_limit_s,
          "must be in (0, 86400]");
  require(speedup >= 0.1 && speedup <= 100.0, "mission.speedup", speedup, "must be in [0.1, 100]");
  require(period_s >= 0.1 && period_s <= 10.0, "mission.period_s", period_s, "must be in [0.1, 10]");
  dds.validate();
  // A building mission may have no avalanche victims or rescuers, but some responder.
  if (!scenario.victims.empty() || !scenario.rescuers.empty() || firefighters.empty()) scenario.validate();
  estimators.validate();
  for (const auto& [id, role] : role_of) {
    if (role == estimator::ResponderRole::kFirefighter && !estimators.firefighter.building) {
      throw ConfigError("rescuers[" + id + "].role = firefighter: the mission has no building: section");
    }
  }
  std::set<std::string> known(sectors.begin(), sectors.end());
  if (known.size() != sectors.size()) throw ConfigError("sectors: duplicate sector name");
  for (const auto& [id, sector] : sector_of) {
    if (!sectors.empty() && known.count(sector) == 0) {
      throw ConfigError("rescuers[" + id + "].sector = '" + sector + "': must be one of the sectors");
    }
    if (sectors.empty() && !sector.empty()) {
      throw ConfigError("rescuers[" + id + "].sector = '" + sector + "': no sectors are defined");
    }
  }
  for (const auto& s : sectors) core_config(s).validate();
  if (sectors.empty()) core_config("").validate();
  for (const auto& [id, role] : role_of) rescuer_config(id).validate();
  for (unsigned k = 1; k <= std::max(1U, command.incident.standby.instances); ++k) command_config(k).validate();
}

dds::CoreNodeConfig MissionConfig::core_config(const std::string& sector) const {
  dds::CoreNodeConfig c = core;
  c.estimators = estimators;
  c.roles = role_of;
  c.partitions = partitions_of_sector(sector);
  c.node_id = core_node_id(sector);
  // Roster mode: the rescuers this daemon serves are the mission's, of its sector; with sector
  // areas, every one of them (any may walk into this sector's area).
  c.roster.listed.clear();
  for (const auto& [id, responder_sector] : sector_of) {
    if (responder_sector == sector || !sector_areas.empty()) c.roster.listed.push_back(id);
  }
  return c;
}

std::string MissionConfig::core_node_id(const std::string& sector) const {
  return sector.empty() ? core.node_id : core.node_id + "-" + sector;
}

std::vector<std::string> MissionConfig::core_node_ids() const {
  if (sectors.empty()) return {core_node_id("")};
  std::vector<std::string> ids;
  for (const auto& sector : sectors) ids.push_back(core_node_id(sector));
  return ids;
}

std::vector<std::string> MissionConfig::security_identities() const {
  std::vector<std::string> ids;
  for (const auto& core_id : core_node_ids()) ids.push_back("core:" + core_id);
  for (unsigned i = 1; i <= command_instances(); ++i) ids.push_back("command:" + command_config(i).node_id);
  for (const auto& avalanche_rescuer : scenario.rescuers) ids.push_back("device:" + avalanche_rescuer.id);
  for (const auto& entry : firefighters) ids.push_back("device:" + entry.id);  // ids are unique across both
  ids.push_back(std::string("dashboard:") + kDashboardIdentity);
  ids.push_back(std::string("recorder:") + kRecorderIdentity);
  ids.push_back(std::string("recorder:") + kMissionIdentity);
  return ids;
}

dds::RescuerNodeConfig MissionConfig::rescuer_config(const std::string& rescuer_id) const {
  dds::RescuerNodeConfig c = rescuer;
  c.rescuer_id = rescuer_id;
  c.team = team_of(rescuer_id);
  c.role = role_of.at(rescuer_id);
  c.estimators = estimators;
  // Waiting longer than half an epoch for the daemon would make the device fall behind.
  c.guidance_wait_s = std::min(c.guidance_wait_s, 0.5 * period_s / speedup);
  const auto it = sector_of.find(rescuer_id);
  c.partitions = partitions_of_sector(it == sector_of.end() ? "" : it->second);
  return c;
}

std::string MissionConfig::team_of(const std::string& responder_id) const {
  for (const auto& f : firefighters) {
    if (f.id == responder_id) return f.team;
  }
  return scenario.rescuers.at(scenario.rescuer_index(responder_id)).team;  // ConfigError when unknown
}

const FirefighterEntry* MissionConfig::firefighter(const std::string& responder_id) const {
  for (const auto& f : firefighters) {
    if (f.id == responder_id) return &f;
  }
  return nullptr;
}

dds::CommandNodeConfig MissionConfig::command_config(unsigned instance) const {
  dds::CommandNodeConfig c = command;
  if (!sectors.empty()) c.estimate_partitions = {"*"};
  c.incident.standby.instance = instance;
  if (c.incident.standby.instances > 1) c.node_id += "-" + std::to_string(instance);
  return c;
}

MissionConfig load_mission_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open mission file");
  std::stringstream text;
  text << in.rdbuf();
  try {
    return load_mission_config_text(text.str(), path, std::filesystem::path(path).parent_path().string());
  } catch (const ConfigError& e) {
    // Every message names the file: a unit that fails at start says which file to fix.
    const std::string what = e.what();
    if (what.find(path) != std::string::npos) throw;
    throw ConfigError(path + ": " + what);
  }
}

MissionConfig load_mission_config_text(const std::string& text, const std::string& name, const std::string& base_dir) {
  MissionConfig c;
  auto root = YamlReader::from_string(text, name);
  double sector_margin_m = 5.0;  // rescuer.sector_margin_m
  bool handover_set = false;     // core.handover_journal_entries is in the file
  {
    auto r = root.child("mission");
    r.read("name", c.name);
    r.read("seed", c.scenario.seed);
    r.read("time_limit_s", c.time_limit_s);
    r.read("speedup", c.speedup);
    r.read("period_s", c.period_s);
    r.expect_done();
  }
  {
    auto r = root.child("incident");
    r.read("id", c.command.incident.incident_id);
    r.read("name", c.command.incident.incident_name);
    r.read("latitude_deg", c.command.incident.origin.latitude_deg);
    r.read("longitude_deg", c.command.incident.origin.longitude_deg);
    r.read("altitude_m", c.command.incident.origin.altitude_m);
    if (r.has("deposit")) {
      c.deposit.emplace(read_outline(r, "deposit", c.command.incident.origin, name), name + ": incident.deposit");
      c.command.incident.deposit = c.deposit;  // incident command plans the search over it
    }
    r.expect_done();
    require_identifier(c.command.incident.incident_id, name + ": incident.id");
  }
  {
    auto r = root.child("dds");
    r.read("profiles_file", c.dds.profiles_file);
    r.read("profile", c.dds.profile);
    r.read("topics_file", c.dds.topics_file);
    r.read("domain_id", c.dds.domain_id);
    r.read("require_security", c.dds.require_security);
    r.read("allow_unauthenticated", c.dds.allow_unauthenticated);
    r.read("security_dir", c.security_dir);
    r.expect_done();
    if (r.has("security_dir")) {
      // One source of the participant profile: a node's secure.xml names it.
      if (r.has("profiles_file") || r.has("profile")) {
        throw ConfigError(name + ": dds.security_dir = '" + c.security_dir +
                          "': each node's profile is <security_dir>/<node>/secure.xml, so dds.profiles_file and "
                          "dds.profile must not be set with it");
      }
      c.security_dir = resolve(c.security_dir, base_dir);
    }
    if (r.has("profiles_file")) c.dds.profiles_file = resolve(c.dds.profiles_file, base_dir);
    if (r.has("topics_file")) c.dds.topics_file = resolve(c.dds.topics_file, base_dir);
  }
  for (auto& r : root.child_list("victims")) {
    mission::VictimSpec v;
    r.read("name", v.name);
    r.require("position", v.position);
    r.require("moment", v.moment);
    double value = 0.0;
    if (r.has("period_ms")) {
      r.read("period_ms", value);
      v.period_ms = value;
    }
    if (r.has("carrier_offset_hz")) {
      r.read("carrier_offset_hz", value);
      v.carrier_offset_hz = value;
    }
    r.expect_done();
    c.scenario.victims.push_back(v);
  }
  for (auto& r : root.child_list("rescuers")) {
    std::string id, team, sector;
    r.require("id", id);
    r.require("team", team);
    r.read("sector", sector);
    require_identifier(id, name + ": " + r.path() + ".id");
    require_identifier(team, name + ": " + r.path() + ".team");
    require_identifier(sector, name + ": " + r.path() + ".sector", true);
    std::string role = estimator::to_string(estimator::ResponderRole::kAvalancheRescuer);
    r.read("role", role);
    const auto parsed_role = estimator::parse_responder_role(role, name + ": " + r.path() + ".role");
    if (parsed_role == estimator::ResponderRole::kFirefighter) {
      // A firefighter enters the mission's building (a simulated one walks a directional search).
      FirefighterEntry f;
      f.id = id;
      f.team = team;
      r.read("entry", f.spec.entry);
      std::string hand = "right";
      r.read("hand", hand);
      if (hand != "right" && hand != "left") {
        throw ConfigError(name + ": " + r.path() + ".hand = '" + hand + "': must be right or left");
      }
      f.spec.hand = hand == "right" ? firefighter::Hand::kRight : firefighter::Hand::kLeft;
      r.read("member", f.spec.member);
      r.read("enter_at_s", f.spec.enter_at_s);
      r.read("search_s", f.spec.search_s);
      r.read("stop_at_s", f.spec.stop_at_s);
      r.read("stop_s", f.spec.stop_s);
      r.read("mayday_at_s", f.spec.mayday_at_s);
      r.read("reset_at_s", f.spec.reset_at_s);
      r.read("recording", f.recording);
      r.read("imu_source", f.imu_source);
      r.expect_done();
      f.spec.validate(r.path());
      // A recording plays on the device as the boot's samples (sarloc-rescuer --source).
      for (auto [key, path] :
           {std::pair<const char*, std::string*>{"recording", &f.recording}, {"imu_source", &f.imu_source}}) {
        *path = resolve(*path, base_dir);
        if (!path->empty() && !std::filesystem::is_regular_file(*path))
          throw ConfigError(name + ": " + r.path() + "." + key + " = '" + *path + "': no such file");
      }
      if (f.recording.empty() && !f.imu_source.empty())
        throw ConfigError(name + ": " + r.path() + ".imu_source = '" + f.imu_source + "': needs a recording");
      // The daemon starts the filter from the entry the team reports; none: unknown start.
      if (!f.spec.entry.empty()) c.estimators.firefighter.entry_of[id] = {f.spec.entry, f.spec.hand};
      c.firefighters.push_back(f);
    } else {
      mission::RescuerSpec s;
      s.id = id;
      s.team = team;
      std::vector<double> start;
      r.require("start", start);
      if (start.size() != 2) throw ConfigError(name + ": " + r.path() + ".start: expected [x, y]");
      s.start = Vec3(start[0], start[1], 0.0);
      r.read("heading_deg", s.heading_deg);
      r.expect_done();
      c.scenario.rescuers.push_back(s);
    }
    if (c.sector_of.count(id) != 0) throw ConfigError(name + ": " + r.path() + ".id = '" + id + "': duplicate rescuer id");
    c.sector_of[id] = sector;
    c.role_of[id] = parsed_role;
  }
  std::vector<incident::SectorAreas::Area> areas;
  for (auto& r : root.child_list("sectors")) {
    std::string sector;
    r.require("name", sector);
    require_identifier(sector, name + ": " + r.path() + ".name");
    if (r.has("area")) areas.push_back({sector, read_outline(r, "area", c.command.incident.origin, name)});
    r.expect_done();
    c.sectors.push_back(sector);
  }
  {
    auto r = root.child("simulation");
    // The mission's own keys first, then the shared sensor model keys.
    r.read("detection_range_m", c.scenario.detection_range_m);
    r.read("gnss_sigma_m", c.scenario.gnss_sigma_m);
    r.read("gnss_correlation_s", c.scenario.gnss_correlation_s);
    r.read("gnss_white_sigma_m", c.scenario.gnss_white_sigma_m);
    r.read("dig_out_after_s", c.scenario.dig_out_after_s);
    read_simulation(r, c.scenario.sensors);
  }
  if (root.has("building")) {
    auto r = root.child("building");
    std::string plan;
    r.require("plan", plan);
    std::vector<double> origin{0.0, 0.0};
    r.read("origin", origin);
    if (origin.size() != 2) throw ConfigError(name + ": building.origin: expected [east, north]");
    auto& f = c.estimators.firefighter;
    f.origin = firefighter::Vec2(origin[0], origin[1]);
    r.read("rotation_deg", f.rotation_deg);
    std::string moved_door;
    double shift_m = 0.0;
    if (r.has("map_error")) {
      auto m = r.child("map_error");
      m.require("door", moved_door);
      m.require("shift_m", shift_m);
      m.expect_done();
    }
    r.expect_done();
    f.seed = c.scenario.seed;
    c.building_path = resolve(plan, base_dir);
    auto world = load_floor_plan(c.building_path);
    firefighter::FloorPlan map = world;
    if (!moved_door.empty()) {
      // The daemon's map is wrong here: the door is elsewhere in the real building.
      bool moved = false;
      for (std::size_t k = 0; k < map.floors.size() && !moved; ++k) {
        for (const auto& d : map.floors[k].doors) moved = moved || d.id == moved_door;
        if (moved) c.map_error_shift_m = firefighter::move_door(map, k, moved_door, shift_m);
      }
      if (!moved) throw ConfigError(name + ": building.map_error.door = '" + moved_door + "': no such door in the plan");
      c.map_error_door = moved_door;
    }
    c.world = std::make_shared<const firefighter::FloorPlan>(std::move(world));
    f.building = std::make_shared<const firefighter::BuildingModel>(std::move(map), firefighter::BuildingModelConfig{});
  }
  {
    auto r = root.child("firefighter");
    auto& f = c.estimators.firefighter;
    r.read("entry_position_sigma_m", f.entry_position_sigma_m);
    r.read("entry_heading_sigma_deg", f.entry_heading_sigma_deg);
    r.read("max_speed_mps", f.max_speed_mps);
    r.read("hint_max_age_s", f.hint_max_age_s);
    r.read("hint_sigma_scale", f.hint_sigma_scale);
    r.read("hint_heading_sigma_deg", f.hint_heading_sigma_deg);
    r.read("hint_max_sigma_m", f.hint_max_sigma_m);
    // Recordings carry their mission file: the two filter keys a mission set before it had
    // firefighter.filter are still read, as the same facts; set both ways, they must agree.
    r.read("particles", f.filter.particles);
    r.read("particles_max", f.filter.particles_max);
    const firefighter::MapFilterConfig direct = f.filter;
    read_map_filter(r.child("filter"), f.filter);  // every key the evaluation tunes, one reader
    if (f.filter.particles != direct.particles || f.filter.particles_max != direct.particles_max) {
      if (r.has("particles") || r.has("particles_max")) {
        throw ConfigError(name + ": firefighter.particles / particles_max and firefighter.filter.particles / "
                          "particles_max disagree: set them in filter: only");
      }
    }
    r.expect_done();
  }
  auto& avalanche = c.estimators.avalanche_rescuer;
  read_sog(root.child("sog"), avalanche.sog);
  read_search(root.child("search"), avalanche.search, &c.command.incident.search_plan);
  read_rescuer_search(root.child("rescuer_search"), avalanche);
  {
    auto r = root.child("triage");
    if (r.has("survival_curve")) {
      c.command.incident.triage.survival_curve.clear();
      for (auto& point : r.child_list("survival_curve")) {
        std::pair<double, double> p;
        point.require("minutes", p.first);
        point.require("probability", p.second);
        point.expect_done();
        c.command.incident.triage.survival_curve.push_back(p);
      }
    }
    r.read("dig_min_per_m", c.command.incident.triage.dig_min_per_m);
    r.read("dig_min_per_m2", c.command.incident.triage.dig_min_per_m2);
    r.read("buried_before_start_min", c.command.incident.triage.buried_before_start_min);
    r.expect_done();
  }
  {
    auto r = root.child("core");
    r.read("node_id", c.core.node_id);
    r.read("workers", c.core.workers);
    std::string admission = "roster";
    r.read("admission", admission);
    if (admission != "roster" && admission != "open") {
      throw ConfigError("core.admission = '" + admission + "': must be roster or open");
    }
    c.core.roster.open = admission == "open";
    unsigned u = static_cast<unsigned>(c.core.roster.max_responders);
    r.read("max_rescuers", u);
    c.core.roster.max_responders = u;
    r.read("idle_evict_s", c.core.roster.idle_evict_s);
    u = static_cast<unsigned>(c.core.queue_limit);
    r.read("queue_limit", u);
    c.core.queue_limit = u;
    r.read("status_period_s", c.core.status_period_s);
    r.read("warning_interval_s", c.core.warning_interval_s);
    r.read("odometry_wait_s", c.core.odometry_wait_s);
    r.read("busy_wait_s", c.core.busy.max_wait_s);
    r.read("busy_utilisation", c.core.busy.max_utilisation);
    r.read("busy_hold_s", c.core.busy.hold_s);
    r.read("busy_shed_wait_s", c.core.busy.shed_wait_s);
    r.read("new_rescuers_per_s", c.core.roster.new_per_s);
    u = static_cast<unsigned>(c.core.handover_journal_entries);
    handover_set = r.has("handover_journal_entries");
    r.read("handover_journal_entries", u);
    c.core.handover_journal_entries = u;
    r.expect_done();
  }
  {
    auto r = root.child("rescuer");
    r.read("fallback_timeout_s", c.rescuer.fallback_timeout_s);
    r.read("guidance_wait_s", c.rescuer.guidance_wait_s);
    r.read("rejoin_epochs", c.rescuer.rejoin_epochs);
    r.read("sector_margin_m", sector_margin_m);
    r.expect_done();
  }
  if (!(sector_margin_m >= 0.0 && sector_margin_m <= 100.0)) {
    throw ConfigError(name + ": rescuer.sector_margin_m = " + config_value(sector_margin_m) +
                      ": must be in [0, 100] m");
  }
  if (!areas.empty()) {
    c.sector_areas = incident::SectorAreas(std::move(areas), sector_margin_m, name + ": sectors");
    // A device walking into another sector's area takes its estimator along: every daemon keeps
    // the journals, unless the file says otherwise (core.handover_journal_entries).
    if (!handover_set) c.core.handover_journal_entries = kHandoverJournalWithAreas;
  }
  {
    auto r = root.child("command");
    r.read("node_id", c.command.node_id);
    r.read("cycle_s", c.command.cycle_s);
    r.read("position_max_age_s", c.command.incident.position_max_age_s);
    r.read("fix_wait_s", c.command.incident.fix_wait_s);
    r.read("fix_interpolation_max_gap_s", c.command.incident.fix_interpolation_max_gap_s);
    r.read("antenna_height_m", c.command.incident.antenna_height_m);  // one fact with sog's: hold_one_antenna_height
    r.read("antenna_height_sigma_m", c.command.incident.antenna_height_sigma_m);
    r.read("instances", c.command.incident.standby.instances);
    r.read("claim_wait_s", c.command.incident.standby.claim_wait_s);
    read_fusion(r.child("fusion"), c.command.incident.fusion);
    {
      auto t = r.child("teams");
      t.read("stale_after_s", c.command.incident.teams.stale_after_s);
      t.read("lost_after_s", c.command.incident.teams.lost_after_s);
      t.expect_done();
    }
    r.expect_done();
  }
  {
    auto r = root.child("record");
    r.read("directory", c.record_directory);  // relative to where the recorder runs
    r.read("allow", c.record.allow);
    r.read("block", c.record.block);
    r.read("partitions", c.record.partitions);
    std::string compression = recording::compression_name(c.record.compression);
    r.read("compression", compression);
    try {
      c.record.compression = recording::parse_compression(compression);
    } catch (const recording::RecordingError& error) {
      throw ConfigError(name + ": record.compression: " + error.what());
    }
    r.read("flush_period_s", c.record.flush_period_s);
    r.read("rotate_size_mb", c.record.rotate_size_mb);
    r.read("rotate_duration_s", c.record.rotate_duration_s);
    r.read("max_queue_mb", c.record.max_queue_mb);
    r.read("sync_on_flush", c.record.sync_on_flush);
    r.expect_done();
    // Checked now with a stand-in path; the real one is chosen per run.
    dds::RecorderConfig check = c.record;
    check.output_path = "check.mcap";
    check.validate();
  }
  {
    auto r = root.child("dashboard");
    auto& d = c.dashboard;
    r.read("bind_address", d.bind_address);
    r.read("port", d.port);
    r.read("token", d.token);
    r.read("view_token", d.view_token);
    r.read("operator_id", d.operator_id);
    r.read("stale_after_s", d.stale_after_s);
    r.read("par_interval_s", d.par_interval_s);
    r.read("push_period_s", d.push_period_s);
    r.read("max_streams", d.max_streams);
    r.read("max_connections_per_address", d.max_connections_per_address);
    r.read("request_deadline_s", d.request_deadline_s);
    r.read("track_length", d.track_length);
    r.read("foxglove_port", d.foxglove_port);
    r.read("feed_origins", d.feed_origins);
    r.read("tls_certificate", d.tls_certificate);
    r.read("hosts", d.hosts);
    r.read("tls_private_key", d.tls_private_key);
    r.read("tls_client_ca", d.tls_client_ca);
    r.read("basemap", d.basemap);
    if (r.has("basemap")) d.basemap = resolve(d.basemap, base_dir);
    if (r.has("tls_certificate")) d.tls_certificate = resolve(d.tls_certificate, base_dir);
    if (r.has("tls_private_key")) d.tls_private_key = resolve(d.tls_private_key, base_dir);
    if (r.has("tls_client_ca")) d.tls_client_ca = resolve(d.tls_client_ca, base_dir);
    r.expect_done();
    d.validate();
  }
  hold_one_antenna_height(root, c.scenario.sensors, c.estimators.avalanche_rescuer.sog, &c.command.incident.antenna_height_m);
  root.expect_done();
  c.validate();
  return c;
}

}  // namespace sarloc::app
