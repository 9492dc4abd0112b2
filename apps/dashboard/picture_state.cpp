#include "picture_state.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>

#include "sarloc/app/incident_geojson.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::dashboard {

using nlohmann::json;

namespace {

double system_wall_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

const char* accountability_name(incident::AccountabilityState s) {
  switch (s) {
    case incident::AccountabilityState::kAccounted: return "accounted";
    case incident::AccountabilityState::kPending: return "pending";
    case incident::AccountabilityState::kMissing: return "missing";
  }
  return "missing";
}

const char* source_name(responder::PositionSource s) {
  switch (s) {
    case responder::PositionSource::kGnss: return "GNSS";
    case responder::PositionSource::kMapAided: return "map-aided";
    case responder::PositionSource::kDeadReckoning: return "dead reckoning";
    case responder::PositionSource::kManual: return "manual";
  }
  return "?";
}

// Positions to the centimetre on the wire: what a map shows, a third of the bytes.
double cm(double metres) { return std::round(metres * 100.0) / 100.0; }


}  // namespace

void PictureStateConfig::validate() const {
  require(track_length >= 1 && track_length <= 10000, "dashboard.track_length", track_length, "must be 1-10000");
  require(event_log_length >= 1 && event_log_length <= 100000, "picture_state.event_log_length", event_log_length,
          "must be 1-100000");
  require(std::isfinite(par_interval_s) && par_interval_s >= 10.0 && par_interval_s <= 86400.0,
          "dashboard.par_interval_s", par_interval_s, "must be in [10, 86400]");
  require(std::isfinite(stale_after_s) && stale_after_s >= 0.5 && stale_after_s <= 3600.0, "dashboard.stale_after_s",
          stale_after_s, "must be in [0.5, 3600]");
}

PictureState::PictureState(PictureStateConfig config, MissionClock mission_now, TimestampNs epoch_ns, WallClock wall_now)
    : config_((config.validate(), config)),
      mission_now_(std::move(mission_now)),
      epoch_ns_(epoch_ns),
      wall_now_(wall_now ? std::move(wall_now) : WallClock(system_wall_s)) {}

void PictureState::set_geodetic_origin(const GeodeticOrigin& origin) {
  std::lock_guard<std::mutex> lock(mutex_);
  geodetic_.emplace(origin);  // ConfigError for an origin out of range: the mission loader's check
}

void PictureState::set_deposit(const std::vector<Eigen::Vector2d>& outline) {
  std::lock_guard<std::mutex> lock(mutex_);
  store_deposit(outline);
}

void PictureState::store_deposit(const std::vector<Eigen::Vector2d>& outline) {
  deposit_ = json::array();
  for (const auto& p : outline) deposit_.push_back({cm(p.x()), cm(p.y())});
  deposit_outline_ = outline;
}

void PictureState::set_building(PlacedPlan b) {
  std::lock_guard<std::mutex> lock(mutex_);
  json floors = json::array();
  const double c = std::cos(b.rotation_rad), s = std::sin(b.rotation_rad);
  auto place = [&](const firefighter::Vec2& p) {
    return std::array<double, 2>{b.origin_x + c * p.x() - s * p.y(), b.origin_y + s * p.x() + c * p.y()};
  };
  for (const auto& floor : b.plan.floors) {
    json walls = json::array(), doors = json::array();
    for (const auto& w : floor.walls) {
      const auto a = place(w.a), e = place(w.b);
      walls.push_back({a[0], a[1], e[0], e[1]});
    }
    for (const auto& d : floor.doors) {
      const auto p = place(d.center);
      doors.push_back({{"id", d.id}, {"x", p[0]}, {"y", p[1]}, {"width_m", d.width_m}});
    }
    floors.push_back({{"id", floor.id}, {"walls", walls}, {"doors", doors}});
  }
  building_ = {{"name", b.plan.name}, {"floors", floors}};
  ++version_;
}

void PictureState::touch_data() { last_data_wall_s_ = wall_now_(); }

void PictureState::event(const std::string& kind, const std::string& text, TimestampNs stamp) {
  ++version_;
  events_.push_back({version_,
                     {{"seq", version_},
                      {"mission_ns", stamp != 0 ? stamp : mission_now_()},
                      {"wall_ms", static_cast<std::int64_t>(wall_now_() * 1e3)},
                      {"kind", kind},
                      {"text", text}}});
  while (events_.size() > config_.event_log_length) events_.pop_front();
}

void PictureState::events(const std::vector<incident::PictureEvent>& changes) {
  for (const auto& e : changes) event(e.kind, e.text, e.stamp);
}

void PictureState::note(const std::string& kind, const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  event(kind, text);
}

void PictureState::on_victim(const incident::FusedVictim& v) {
  std::lock_guard<std::mutex> lock(mutex_);
  touch_data();
  events(picture_events_.on_victim(v));
  ++version_;
  victims_[v.victim_id] = {v, version_};
}

void PictureState::on_victim_gone(std::uint32_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (victims_.erase(id) == 0) return;
  events(picture_events_.on_victim_gone(id, mission_now_()));
  note_removed("victim", id);
}

void PictureState::note_removed(const char* kind, std::uint32_t id) {
  removed_.push_back({++version_, {kind, std::to_string(id)}});
  if (removed_.size() <= kRemovedKept) return;
  removed_floor_ = removed_.front().first;
  removed_.pop_front();
}

void PictureState::on_team(const incident::TeamStatus& t) {
  std::lock_guard<std::mutex> lock(mutex_);
  touch_data();
  auto [it, fresh] = teams_.try_emplace(t.team_id);
  auto& team = it->second;
  if (fresh) team.par_due_wall_s = wall_now_() + config_.par_interval_s;
  events(picture_events_.on_team(t));
  team.status = t;
  team.version = ++version_;
}

void PictureState::on_alarm(const incident::IncidentAlarm& a) {
  std::lock_guard<std::mutex> lock(mutex_);
  touch_data();
  // Incident command republishes every alarm each cycle: only a change goes to the pages.
  const auto it = alarms_.find(a.alarm_id);
  if (it != alarms_.end() && incident::same_alarm(it->second.first, a)) return;
  events(picture_events_.on_alarm(a));
  ++version_;
  alarms_[a.alarm_id] = {a, version_};
}

void PictureState::on_alarm_gone(std::uint32_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (alarms_.erase(id) == 0) return;
  events(picture_events_.on_alarm_gone(id, mission_now_()));
  note_removed("alarm", id);
}

void PictureState::on_position(const responder::ResponderPosition& p) {
  std::lock_guard<std::mutex> lock(mutex_);
  touch_data();
  events(picture_events_.on_position(p));
  auto& r = responders_[p.responder_id];
  // A device's dead reckoning does not replace a fresh map-aided fix on the map.
  if (r.version > 0 && r.last.source == responder::PositionSource::kMapAided &&
      p.source == responder::PositionSource::kDeadReckoning && p.stamp - r.last.stamp < 3'000'000'000LL) {
    return;
  }
  if (r.version > 0 && p.stamp < r.last.stamp) return;  // out of order: keep the newest
  // The core daemon's copy of a silent firefighter's last position: nothing moved.
  if (r.version > 0 && p.stamp == r.last.stamp && p.source == r.last.source) return;
  r.last = p;
  r.track.push_back({p.position.position.x(), p.position.position.y()});
  while (r.track.size() > config_.track_length) r.track.pop_front();
  r.version = ++version_;
}

void PictureState::on_candidates(const responder::ResponderCandidates& c) {
  std::lock_guard<std::mutex> lock(mutex_);
  touch_data();
  auto& newest = candidates_[c.responder_id];
  if (c.stamp < newest.stamp) return;  // out of order: keep the newest
  newest = c;
  // No position yet: nothing is drawn until one comes.
  if (auto it = responders_.find(c.responder_id); it != responders_.end()) it->second.version = ++version_;
}

void PictureState::on_guidance(const responder::Guidance& g) {
  std::lock_guard<std::mutex> lock(mutex_);
  touch_data();
  auto it = responders_.find(g.rescuer_id);
  if (it == responders_.end()) return;  // no position yet: nowhere to draw the arrow
  it->second.guidance_heading_rad = g.heading_rad;
  it->second.version = ++version_;
}

void PictureState::on_picture_writer(const std::string& participant) {
  std::lock_guard<std::mutex> lock(mutex_);
  touch_data();
  if (participant == picture_writer_) return;
  if (!picture_writer_.empty()) event("command", "incident picture now published by another instance (failover): " + participant.substr(0, 8));
  picture_writer_ = participant;
}

void PictureState::on_rejected(const std::string& topic) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++rejected_[topic];
}

bool PictureState::par_reported(const std::string& team_id, const std::string& operator_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = teams_.find(team_id);
  if (it == teams_.end()) return false;
  it->second.par_due_wall_s = wall_now_() + config_.par_interval_s;
  it->second.version = ++version_;
  event("accountability", "PAR of team " + team_id + " reported (" + operator_id + ")");
  return true;
}

json PictureState::victim_json(const incident::FusedVictim& v) const {
  const auto& c = v.position.covariance;
  std::vector<std::string> sources;
  for (const auto& s : v.sources) sources.push_back(s.rescuer_id + "/" + std::to_string(s.signal_id));
  json out = {{"id", v.victim_id},
              {"state", incident::to_string(v.state)},
              {"x", v.position.position.x()},
              {"y", v.position.position.y()},
              {"z", v.position.position.z()},
              {"cov", {c(0, 0), c(0, 1), c(1, 1)}},
              {"radius95_m", radius95_2d(c)},
              {"floor", v.floor},
              {"located_ns", v.located_at},
              {"found_ns", v.found_at},
              {"sources", sources},
              {"conflict", v.evidence_conflict},
              {"possibly_same_as", v.possibly_same_as}};
  if (geodetic_ && v.position.position.allFinite())
    out["wgs84"] = incident::format_wgs84(geodetic_->to_wgs84(v.position.position));
  return out;
}

json PictureState::responder_json(const std::string& id, const Responder& r, bool with_track) const {
  const auto& c = r.last.position.covariance;
  json out = {{"id", id},
              {"team", r.last.team_id},
              {"x", cm(r.last.position.position.x())},
              {"y", cm(r.last.position.position.y())},
              {"cov", {c(0, 0), c(0, 1), c(1, 1)}},
              {"floor", r.last.floor},
              {"source", source_name(r.last.source)},
              {"converged", r.last.converged},
              {"confirmed", r.last.confirmed},
              {"ambiguous", r.last.ambiguous},
              {"map_error", r.last.map_error_suspected},
              {"stamp_ns", r.last.stamp},
              {"heading_rad", r.guidance_heading_rad ? json(*r.guidance_heading_rad) : json(nullptr)}};
  // Where an ambiguous firefighter may be: each place with its share, heaviest first.
  constexpr TimestampNs kCandidatesOfItsTimeNs = 5'000'000'000;
  json candidates = json::array();
  const auto places = candidates_.find(id);
  if (r.last.ambiguous && places != candidates_.end() &&
      std::llabs(places->second.stamp - r.last.stamp) <= kCandidatesOfItsTimeNs) {
    for (const auto& p : places->second.candidates) {
      const auto& pc = p.position.covariance;
      candidates.push_back({{"x", cm(p.position.position.x())},
                            {"y", cm(p.position.position.y())},
                            {"cov", {pc(0, 0), pc(0, 1), pc(1, 1)}},
                            {"floor", p.floor},
                            {"weight", std::round(1000.0 * p.weight) / 1000.0}});
    }
  }
  out["candidates"] = std::move(candidates);
  if (with_track) {
    json track = json::array();
    for (const auto& p : r.track) track.push_back({cm(p[0]), cm(p[1])});
    out["track"] = std::move(track);
  }
  return out;
}

json PictureState::team_json(const Team& t) const {
  json members = json::array();
  for (const auto& m : t.status.members) {
    members.push_back({{"id", m.responder_id},
                       {"link", incident::to_string(m.link)},
                       {"accountability", accountability_name(m.accountability)},
                       {"last_seen_ns", m.last_seen},
                       {"floor", m.floor}});
  }
  return {{"id", t.status.team_id}, {"members", members}, {"par_due_wall_ms", static_cast<std::int64_t>(t.par_due_wall_s * 1e3)}};
}

json PictureState::alarm_json(const incident::IncidentAlarm& a) const {
  return {{"id", a.alarm_id},
          {"kind", responder::to_string(a.alarm.kind)},
          {"name", responder::display_name(a.alarm.kind)},
          {"responder", a.alarm.responder_id},
          {"team", a.alarm.team_id},
          {"raised_ns", a.alarm.raised_at},
          {"active", a.alarm.active},
          {"cleared_ns", a.alarm.cleared_at},
          {"acknowledged", a.acknowledged},
          {"acknowledged_by", a.acknowledged_by},
          {"position_known", a.alarm.position_known},
          {"x", a.alarm.last_position.position.x()},
          {"y", a.alarm.last_position.position.y()},
          {"floor", a.alarm.floor}};
}

namespace {

// One rescuer per victim: who incident command sends to each victim heard by several.
std::map<std::uint32_t, std::string> pursuers_of(const incident::SearchPlanPicture& plan) {
  std::map<std::uint32_t, std::string> out;
  for (const auto& h : plan.handed_over)
    if (h.victim_id != 0) out[h.victim_id] = h.pursued_by;  // 0: a transmitter not yet placed
  return out;
}

// One rescuer per signal before anyone has placed it: each pursuer and the other rescuers whose
// signal of that transmitter is handed over to him.
std::map<std::string, std::set<std::string>> unplaced_pursuits_of(const incident::SearchPlanPicture& plan) {
  std::map<std::string, std::set<std::string>> out;
  for (const auto& h : plan.handed_over)
    if (h.victim_id == 0) out[h.pursued_by].insert(h.rescuer_id);
  return out;
}

// What the dig order shows: victims in order, their diggers and survival in whole percent (the
// minutes buried grow every cycle; the page need not be sent each time).
std::string dig_order_key(const incident::SearchPlanPicture& plan) {
  std::string key;
  for (const auto& d : plan.digs.digs)
    key +=
        std::to_string(d.victim_id) + ":" + d.digger_id + ":" + std::to_string(std::lround(100.0 * d.survival)) + ";";
  return key;
}

}  // namespace

void PictureState::on_search_plan(const incident::SearchPlanPicture& plan) {
  std::lock_guard<std::mutex> lock(mutex_);
  touch_data();
  // The plan's deposit is the one incident command plans over: an operator may have drawn it.
  const bool new_deposit = !plan.deposit.empty() && plan.deposit != deposit_outline_;
  if (new_deposit) store_deposit(plan.deposit);
  const bool changed = new_deposit || !plan_ || plan_->plan.revision != plan.plan.revision ||
                       plan_->plan.searched != plan.plan.searched || pursuers_of(*plan_) != pursuers_of(plan) ||
                       unplaced_pursuits_of(*plan_) != unplaced_pursuits_of(plan) ||
                       dig_order_key(*plan_) != dig_order_key(plan);
  plan_ = plan;
  if (changed) plan_version_ = ++version_;
}

json PictureState::plan_json() const {
  json strips = json::array();
  for (std::size_t i = 0; i < plan_->plan.strips.size(); ++i) {
    const auto& s = plan_->plan.strips[i];
    json outline = json::array();
    for (const auto& p : s.strip.outline) outline.push_back({cm(p.x()), cm(p.y())});
    const auto& next = i < plan_->next_points.size() ? plan_->next_points[i] : std::nullopt;
    const auto& helper_next = i < plan_->helper_next_points.size() ? plan_->helper_next_points[i] : std::nullopt;
    strips.push_back({{"index", s.strip.index},
                      {"outline", outline},
                      {"top", {cm(s.strip.top.x()), cm(s.strip.top.y())}},
                      {"searched", s.searched},
                      {"done", s.done},
                      {"rescuer", s.rescuer_id},
                      {"next", next ? json{cm(next->x()), cm(next->y())} : json(nullptr)},
                      {"helper", s.helper_id},
                      {"helper_next", helper_next ? json{cm(helper_next->x()), cm(helper_next->y())} : json(nullptr)}});
  }
  // One rescuer per victim: who incident command sends to each victim heard by several.
  json pursuers = json::object();
  for (const auto& [victim, rescuer] : pursuers_of(*plan_)) pursuers[std::to_string(victim)] = rescuer;
  json unplaced = json::array();
  for (const auto& [pursuer, others] : unplaced_pursuits_of(*plan_))
    unplaced.push_back({{"pursuer", pursuer}, {"others", others}});
  // Triage: the FOUND victims in the order incident command would dig them out.
  json digs = json::array();
  for (const auto& d : plan_->digs.digs)
    digs.push_back({{"victim", d.victim_id},
                    {"depth_m", d.depth_m},
                    {"buried_min", d.buried_min},
                    {"start_min", d.start_min},
                    {"done_min", d.done_min},
                    {"survival", d.survival},
                    {"digger", d.digger_id}});
  return {{"revision", plan_->plan.revision},
          {"searched", plan_->plan.searched},
          {"strips", strips},
          {"pursuers", pursuers},
          {"unplaced_pursuits", unplaced},
          {"digs", digs},
          {"expected_survivors", plan_->digs.expected_survivors},
          {"deposit", deposit_}};
}

json PictureState::collect(std::uint64_t since, bool with_tracks) const {
  json out = {{"version", version_},
              {"mission_ns", mission_now_()},
              {"epoch_ns", epoch_ns_},
              {"wall_ms", static_cast<std::int64_t>(wall_now_() * 1e3)}};
  json victims = json::array(), responders = json::array(), teams = json::array(), alarms = json::array(), events = json::array(),
       removed = json::array();
  for (const auto& [id, v] : victims_) {
    if (v.second > since) victims.push_back(victim_json(v.first));
  }
  for (const auto& [id, r] : responders_) {
    if (r.version > since) responders.push_back(responder_json(id, r, with_tracks));
  }
  for (const auto& [id, t] : teams_) {
    if (t.version > since) teams.push_back(team_json(t));
  }
  for (const auto& [id, a] : alarms_) {
    if (a.second > since) alarms.push_back(alarm_json(a.first));
  }
  for (const auto& [v, e] : events_) {
    if (v > since) events.push_back(e);
  }
  for (const auto& [v, r] : removed_) {
    if (v > since) removed.push_back({{"kind", r.first}, {"id", r.second}});
  }
  out["victims"] = victims;
  out["responders"] = responders;
  out["teams"] = teams;
  out["alarms"] = alarms;
  out["events"] = events;
  out["removed"] = removed;
  if (plan_ && plan_version_ > since) out["plan"] = plan_json();
  return out;
}

void PictureState::reset() {
  std::lock_guard<std::mutex> lock(mutex_);
  victims_.clear();
  responders_.clear();
  candidates_.clear();
  teams_.clear();
  alarms_.clear();
  events_.clear();
  picture_events_ = {};
  removed_.clear();
  picture_writer_.clear();
  rejected_.clear();
  plan_.reset();
  last_data_wall_s_ = -1.0;
  reset_version_ = ++version_;
}

bool PictureState::needs_snapshot(std::uint64_t since) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stale(since);
}

void PictureState::set_extra(const std::string& key, json value) {
  std::lock_guard<std::mutex> lock(mutex_);
  extra_[key] = std::move(value);
}

json PictureState::snapshot() const {
  std::lock_guard<std::mutex> lock(mutex_);
  json out = collect(0, true);
  for (const auto& [key, value] : extra_.items()) out[key] = value;
  out["type"] = "snapshot";
  out["removed"] = json::array();
  out["building"] = building_;
  out["deposit"] = deposit_;
  out["rejected"] = rejected_;
  out["par_interval_s"] = config_.par_interval_s;
  return out;
}

json PictureState::delta(std::uint64_t since) const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!stale(since)) {
      json out = collect(since, false);
      out["type"] = "delta";
      return out;
    }
  }
  return snapshot();  // rebuilt since: what the page holds is void
}

json PictureState::heartbeat() const {
  std::lock_guard<std::mutex> lock(mutex_);
  const double age = last_data_wall_s_ < 0 ? -1.0 : wall_now_() - last_data_wall_s_;
  json out = {{"type", "heartbeat"},
          {"version", version_},
          {"mission_ns", mission_now_()},
          {"epoch_ns", epoch_ns_},
          {"wall_ms", static_cast<std::int64_t>(wall_now_() * 1e3)},
          {"data_age_s", age},
          {"stale", age < 0 || age > config_.stale_after_s}};
  for (const auto& [key, value] : extra_.items()) out[key] = value;
  return out;
}

std::uint64_t PictureState::version() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

std::size_t PictureState::victim_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return victims_.size();
}

std::optional<json> PictureState::geojson() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!geodetic_) return std::nullopt;
  app::IncidentGeoJson picture;
  picture.epoch_ns = epoch_ns_;
  if (!deposit_outline_.empty()) picture.deposit = deposit_outline_;
  if (plan_) {
    for (const auto& s : plan_->plan.strips)
      picture.strips.push_back({s.strip.index, s.strip.outline, s.strip.width_m, s.searched});
  }
  for (const auto& [id, r] : responders_) {
    const bool outdoors =
        r.last.source == responder::PositionSource::kGnss || r.last.source == responder::PositionSource::kManual;
    app::GeoJsonTrack track{id, r.last.team_id, outdoors ? "avalanche rescuer" : "firefighter", {}};
    for (const auto& p : r.track) track.points.emplace_back(p[0], p[1]);
    picture.tracks.push_back(std::move(track));
  }
  const auto mission_s = [&](TimestampNs t) {
    return t == 0 ? std::optional<double>() : std::optional<double>(static_cast<double>(t - epoch_ns_) * 1e-9);
  };
  for (const auto& [id, entry] : victims_) {
    const incident::FusedVictim& v = entry.first;
    std::vector<std::string> sources;
    for (const auto& s : v.sources) sources.push_back(s.rescuer_id + "/" + std::to_string(s.signal_id));
    picture.victims.push_back({id, incident::to_string(v.state), v.position, mission_s(v.located_at),
                               mission_s(v.found_at), sources, v.evidence_conflict});
  }
  return app::to_geojson(picture, *geodetic_);
}

}  // namespace sarloc::dashboard
