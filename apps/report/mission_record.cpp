#include "mission_record.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>

#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/number_text.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"
#include "sarloc/core/incident/picture_events.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/recorded_sample.hpp"
#include "sarloc/dds/replayer.hpp"
#include "sarloc/dds/topics.hpp"

namespace sarloc::report {

namespace {

class Loader {
 public:
  explicit Loader(MissionRecord& record) : r_(record) {}

  void on_metadata(const recording::Metadata& m) {
    if (m.name == "sarloc.recording") {
      r_.recording_metadata = m.values;
    } else if (m.name == "sarloc.recorder_counters") {
      for (const auto& [topic, text] : m.values) parse_counters_text(topic, text);
    }
  }

  void on_channel(const recording::Channel& c) { topics_[c.id] = c.topic; }

  void on_message(const recording::Message& m) {
    const auto topic_it = topics_.find(m.channel_id);
    if (topic_it == topics_.end()) return;
    const std::string& topic = topic_it->second;
    if (first_log_ns_ == 0) first_log_ns_ = m.log_time_ns;
    last_log_ns_ = std::max(last_log_ns_, m.log_time_ns);
    if (topic == "sarloc/recorder_status") return on_status_json(m);
    if (topic == "sarloc/recorder_events") return on_event_json(m);
    auto& quality = r_.quality[topic];
    ++quality.recorded;
    try {
      if (const auto sample = dds::decode_recorded(topic, m.data)) {
        std::visit([&](const auto& decoded) { take(decoded, m); }, *sample);
      }
    } catch (const std::exception&) {
      ++quality.undecodable;  // a bad sample loses nothing else
    }
  }

  void finish() {
    auto& md = r_.recording_metadata;
    r_.mission_name = md.count("mission") ? md["mission"] : "(unnamed recording)";
    // Times: the metadata's epoch; without it the first message is time 0.
    if (r_.epoch_ns == 0) r_.epoch_ns = static_cast<std::int64_t>(first_log_ns_);
    r_.duration_s = last_log_ns_ > 0 ? wall_to_mission(last_log_ns_) : 0.0;
    // Victim histories were gathered as (stamp) pairs: to mission seconds.
    finish_victims();
    finish_positions();
    finish_nodes();
    finish_truth();
    finish_planned_deposit();
    std::stable_sort(r_.events.begin(), r_.events.end(), [](const Event& a, const Event& b) { return a.t_s < b.t_s; });
  }

  void set_epoch_from_metadata() {
    try {
      const auto timeline = dds::timeline_of(r_.recording_metadata);
      r_.epoch_ns = timeline.epoch_ns;
      r_.speedup = timeline.speedup;
    } catch (const ConfigError&) {
      r_.notes.push_back("the recording's epoch_ns/speedup metadata do not parse: times count from its first message");
    }
  }

 private:
  // What the report draws from each recorded sample; the rest was decoded only to check that
  // it is whole.
  void take(const responder::ResponderPosition& p, const recording::Message&) { on_position(p); }
  void take(const incident::FusedVictim& v, const recording::Message&) { on_victim(v); }
  void take(const incident::TeamStatus& t, const recording::Message&) { on_team(t); }
  void take(const incident::IncidentAlarm& a, const recording::Message&) { on_alarm(a); }
  void take(const ::sarloc::NodeStatus& n, const recording::Message& m) { on_node_status(n, m); }
  void take(const incident::IncidentFrame& f, const recording::Message&) { r_.incident_origin = f.origin; }
  void take(const incident::SearchPlanPicture& p, const recording::Message&) { r_.search_plan = p; }
  void take(const ::sarloc::VictimRecovery& recovery, const recording::Message&) {
    r_.events.push_back({stamp_to_mission(recovery.stamp()), "victim",
                         "victim " + std::to_string(recovery.victim_id()) + " reported dug out by " +
                             dds::printable_id(recovery.reported_by())});
  }
  template <class T>
  void take(const T&, const recording::Message&) {}

  double stamp_to_mission(TimestampNs stamp) const { return 1e-9 * static_cast<double>(stamp - r_.epoch_ns); }
  double wall_to_mission(std::uint64_t log_ns) const {
    return 1e-9 * r_.speedup * (static_cast<double>(log_ns) - static_cast<double>(r_.epoch_ns));
  }

  void on_position(const responder::ResponderPosition& p) {
    if (p.source == responder::PositionSource::kMapAided) {
      // The core daemon writes a silent firefighter's last position again (a second daemon its
      // older one): one point of his track, in time order, as incident command keeps it.
      auto [newest, first] = newest_map_aided_.try_emplace(p.responder_id, p.stamp);
      if (!first && p.stamp <= newest->second) return;
      newest->second = p.stamp;
      add_events(picture_events_.on_position(p));
    }
    auto& track = r_.responders[p.responder_id];
    track.id = p.responder_id;
    if (!p.team_id.empty()) track.team = p.team_id;
    PositionSample s;
    s.t_s = stamp_to_mission(p.stamp);
    s.position = p.position;
    s.floor = p.floor;
    s.source = p.source;
    s.converged = p.converged;
    s.confirmed = p.confirmed;
    s.map_error_suspected = p.map_error_suspected;
    if (p.source == responder::PositionSource::kMapAided || p.source == responder::PositionSource::kDeadReckoning) {
      track.firefighter = true;
    }
    track.samples.push_back(s);
  }

  void on_victim(const incident::FusedVictim& v) {
    auto& h = r_.victims[v.victim_id];
    h.id = v.victim_id;
    h.samples.push_back({stamp_to_mission(v.last_update), v.position, v.state});
    if (v.located_at != 0 && !h.located_s) h.located_s = stamp_to_mission(v.located_at);
    if (v.found_at != 0 && !h.found_s) h.found_s = stamp_to_mission(v.found_at);
    h.evidence_conflict = h.evidence_conflict || v.evidence_conflict;
    for (const auto& s : v.sources) {
      const std::string name = s.rescuer_id + "/" + std::to_string(s.signal_id);
      if (std::find(h.sources.begin(), h.sources.end(), name) == h.sources.end()) h.sources.push_back(name);
    }
    add_events(picture_events_.on_victim(v));
  }

  void on_team(const incident::TeamStatus& t) {
    for (const auto& m : t.members) {
      auto& track = r_.responders[m.responder_id];
      track.id = m.responder_id;
      track.team = t.team_id;
    }
    add_events(picture_events_.on_team(t));
  }

  void on_alarm(const incident::IncidentAlarm& a) { add_events(picture_events_.on_alarm(a)); }

  void add_events(const std::vector<incident::PictureEvent>& events) {
    for (const auto& e : events) r_.events.push_back({stamp_to_mission(e.stamp), e.kind, e.text});
  }

  void on_node_status(const ::sarloc::NodeStatus& n, const recording::Message& m) {
    const std::string id = n.node_id().to_string();
    auto& rejects = r_.node_rejects[id];
    rejects.clear();
    for (const auto& c : n.rejects()) rejects[c.reason().to_string()] = c.count();
    if (n.kind() == ::sarloc::NODE_CORE) {
      auto& heard = core_heard_[id];
      const double t = wall_to_mission(m.log_time_ns);
      if (heard.any && (t - heard.last_t) * 1.0 / r_.speedup > kSilentWall_s) {
        r_.events.push_back({heard.last_t, "daemon", "core daemon " + id + " silent: rescuers guide on their own devices"});
        r_.events.push_back(
            {t, "daemon", "core daemon " + id + " heard again after " + one_decimal(t - heard.last_t) + " mission s"});
      }
      heard = {true, t};
    }
    const auto participant = first_samples_.find({m.log_time_ns, m.sequence});
    if (participant != first_samples_.end()) node_of_participant_[participant->second] = id;
  }

  void on_status_json(const recording::Message& m) {
    try {
      const auto j = nlohmann::json::parse(m.data.begin(), m.data.end());
      for (const auto& [topic, c] : j.at("topics").items()) {
        auto& q = r_.quality[topic];
        q.received = c.value("received", 0ull);
        q.written = c.value("written", 0ull);
        q.lost = c.value("lost", 0ull);
        q.rejected.clear();
        for (const auto& [reason, n] : c.at("rejected").items()) q.rejected[reason] = n.get<std::uint64_t>();
      }
    } catch (const std::exception&) {
      r_.notes.push_back("a recorder status message does not parse");
    }
  }

  void on_event_json(const recording::Message& m) {
    try {
      const auto j = nlohmann::json::parse(m.data.begin(), m.data.end());
      if (j.value("event", "") != "writer_seen") return;
      const std::string topic = j.at("topic");
      const std::string participant = j.at("participant");
      first_samples_[{j.at("log_time_ns").get<std::uint64_t>(), j.at("sequence").get<std::uint32_t>()}] = participant;
      if (topic == "sarloc/incident_summary") picture_writers_.push_back({m.log_time_ns, participant});
      if (topic == "sarloc/node_status") node_participants_.push_back({m.log_time_ns, participant});
    } catch (const std::exception&) {
      r_.notes.push_back("a recorder event does not parse");
    }
  }

  void parse_counters_text(const std::string& topic, const std::string& text) {
    // "received=N written=N lost=N rejected=reason:N,..." (the final counters of the recorder)
    auto& q = r_.quality[topic];
    auto number = [&](const std::string& key) -> std::uint64_t {
      const auto at = text.find(key + "=");
      if (at == std::string::npos) return 0;
      try {
        return std::stoull(text.substr(at + key.size() + 1));
      } catch (const std::exception&) {
        return 0;
      }
    };
    q.received = number("received");
    q.written = number("written");
    q.lost = number("lost");
  }

  void finish_victims() {
    for (auto& [id, h] : r_.victims) {
      std::stable_sort(h.samples.begin(), h.samples.end(), [](const auto& a, const auto& b) { return a.t_s < b.t_s; });
    }
  }

  void finish_positions() {
    for (auto& [id, track] : r_.responders) {
      std::stable_sort(track.samples.begin(), track.samples.end(),
                       [](const auto& a, const auto& b) { return a.t_s < b.t_s; });
    }
  }

  void finish_nodes() {
    // A core daemon's node id published by a second participant: it was restarted.
    std::map<std::string, std::string> participant_of_node;
    for (const auto& [log_ns, participant] : node_participants_) {
      const auto node = node_of_participant_.find(participant);
      if (node == node_of_participant_.end()) continue;
      const auto before = participant_of_node.find(node->second);
      if (before != participant_of_node.end() && before->second != participant) {
        r_.events.push_back({wall_to_mission(log_ns), "daemon", node->second + " restarted (a new participant)"});
      }
      participant_of_node[node->second] = participant;
    }
    // The incident picture written by another participant than before: a failover.
    std::string current;
    for (const auto& [log_ns, participant] : picture_writers_) {
      const auto node = node_of_participant_.find(participant);
      const std::string name = node == node_of_participant_.end() ? "participant " + participant.substr(0, 8) : node->second;
      if (current.empty()) {
        r_.events.push_back({wall_to_mission(log_ns), "command", "incident picture published by " + name});
      } else if (current != participant) {
        r_.events.push_back({wall_to_mission(log_ns), "command", "FAILOVER: incident picture now published by " + name});
      }
      current = participant;
    }
    for (const auto& [id, heard] : core_heard_) {
      if ((r_.duration_s - heard.last_t) / r_.speedup > kSilentWall_s) {
        r_.events.push_back({heard.last_t, "daemon", "core daemon " + id + " silent until the end of the recording"});
      }
    }
  }

  void finish_truth() {
    auto& md = r_.recording_metadata;
    if (!md.count("mission_yaml")) {
      r_.notes.push_back("no mission file in the recording: no truth to compare with (not recorded by sarloc-mission)");
      return;
    }
    try {
      const YAML::Node root = YAML::Load(md["mission_yaml"]);
      finish_deposit(root["incident"]);
      for (const auto& v : root["victims"]) {
        const auto p = v["position"].as<std::vector<double>>();
        if (p.size() == 3) r_.truth_victims.push_back({v["name"].as<std::string>(""), Vec3(p[0], p[1], p[2])});
      }
      for (const auto& rescuer : root["rescuers"]) {
        const std::string id = rescuer["id"].as<std::string>("");
        if (rescuer["role"].as<std::string>("") == "firefighter") r_.responders[id].firefighter = true;
        if (r_.responders.count(id)) {
          r_.responders[id].id = id;
          if (r_.responders[id].team.empty()) r_.responders[id].team = rescuer["team"].as<std::string>("");
        }
      }
      if (root["building"] && md.count("building_plan_yaml")) {
        PlacedBuilding b;
        b.plan = app::load_floor_plan_text(md["building_plan_yaml"], "the recording's building_plan_yaml");
        const auto origin = root["building"]["origin"].as<std::vector<double>>(std::vector<double>{0.0, 0.0});
        if (origin.size() == 2) b.origin = Eigen::Vector2d(origin[0], origin[1]);
        b.rotation_rad = root["building"]["rotation_deg"].as<double>(0.0) * kPi / 180.0;
        r_.building = std::move(b);
      }
      r_.notes.push_back("firefighters' true tracks are not recorded (they live in the simulated devices): no RMSE for them");
    } catch (const std::exception& error) {
      r_.notes.push_back(std::string("the recorded mission file does not parse: ") + error.what());
    }
  }

  // The deposit incident command last planned over: the mission file's, or an operator's drawn
  // in its place (DepositDrawing), which the report must show instead.
  void finish_planned_deposit() {
    if (!r_.search_plan || r_.search_plan->deposit.empty()) return;
    auto sorted = [](std::vector<incident::Vec2> v) {
      std::sort(v.begin(), v.end(),
                [](const auto& a, const auto& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
      return v;
    };
    const auto planned = sorted(r_.search_plan->deposit);
    if (r_.deposit) {
      const auto mission = sorted(r_.deposit->vertices());
      bool same = mission.size() == planned.size();
      for (std::size_t i = 0; same && i < planned.size(); ++i) same = (mission[i] - planned[i]).norm() < 0.01;
      if (same) return;
    }
    try {
      const bool replaced = r_.deposit.has_value();
      r_.deposit.emplace(r_.search_plan->deposit, "the recorded search plan's deposit");
      if (replaced)
        r_.notes.push_back(
            "the deposit shown is the one the last recorded plan covers (drawn by an operator), not the mission "
            "file's");
    } catch (const std::exception& error) {
      r_.notes.push_back(std::string("the recorded plan's deposit is not usable: ") + error.what());
    }
  }

  // The origin and the deposit as the mission loader read them (mission_config.cpp): the deposit's
  // WGS-84 outline at the origin's altitude, into the incident frame. A recording whose incident
  // command published no IncidentFrame takes the origin from the file too.
  void finish_deposit(const YAML::Node& incident_node) {
    if (!incident_node) return;
    GeodeticOrigin origin;
    origin.latitude_deg = incident_node["latitude_deg"].as<double>(origin.latitude_deg);
    origin.longitude_deg = incident_node["longitude_deg"].as<double>(origin.longitude_deg);
    origin.altitude_m = incident_node["altitude_m"].as<double>(origin.altitude_m);
    if (!r_.incident_origin) r_.incident_origin = origin;
    if (!incident_node["deposit"]) return;
    try {
      const incident::GeodeticFrame frame(origin);
      std::vector<incident::Vec2> outline;
      for (const auto& vertex : incident_node["deposit"]) {
        incident::Geodetic g;
        g.latitude_deg = vertex["latitude_deg"].as<double>();
        g.longitude_deg = vertex["longitude_deg"].as<double>();
        g.altitude_m = origin.altitude_m;
        outline.push_back(frame.to_enu(g).head<2>());
      }
      r_.deposit.emplace(outline, "the recorded mission file's incident.deposit");
    } catch (const std::exception& error) {
      r_.notes.push_back(std::string("the recorded deposit is not usable: ") + error.what());
    }
  }

  static constexpr double kSilentWall_s = 3.0;  // a node status is expected every second

  struct Heard {
    bool any = false;
    double last_t = 0.0;
  };

  MissionRecord& r_;
  std::map<std::uint16_t, std::string> topics_;
  std::uint64_t first_log_ns_ = 0, last_log_ns_ = 0;
  incident::PictureEvents picture_events_;
  std::map<std::string, TimestampNs> newest_map_aided_;  ///< per responder, its copies skipped
  std::map<std::string, Heard> core_heard_;
  std::map<std::pair<std::uint64_t, std::uint32_t>, std::string> first_samples_;  // (log, seq) -> participant
  std::map<std::string, std::string> node_of_participant_;
  std::vector<std::pair<std::uint64_t, std::string>> picture_writers_, node_participants_;
};

}  // namespace

Eigen::Vector2d PlacedBuilding::to_incident(const Eigen::Vector2d& p) const {
  const double c = std::cos(rotation_rad), s = std::sin(rotation_rad);
  return origin + Eigen::Vector2d(c * p.x() - s * p.y(), s * p.x() + c * p.y());
}


MissionRecord load_mission_record(const std::string& path, const std::function<void(std::uint64_t, std::uint64_t)>& on_progress) {
  MissionRecord record;
  record.path = path;
  // Two passes: the metadata first (the epoch is needed to place every message in mission time;
  // it sits at the start of a sarloc file, but a reader must not rely on that).
  Loader metadata_pass(record);
  recording::McapVisitor first;
  first.on_metadata = [&](const recording::Metadata& m) { metadata_pass.on_metadata(m); };
  recording::read_mcap(path, first);
  metadata_pass.set_epoch_from_metadata();

  Loader loader(record);
  recording::McapVisitor visitor;
  visitor.on_channel = [&](const recording::Channel& c) { loader.on_channel(c); };
  visitor.on_message = [&](const recording::Message& m) { loader.on_message(m); };
  visitor.on_metadata = [&](const recording::Metadata& m) { loader.on_metadata(m); };
  visitor.on_progress = on_progress;
  record.read = recording::read_mcap(path, visitor);
  loader.finish();
  return record;
}

}  // namespace sarloc::report
