// The report's reading of a recording, on a recording made here with known content: victims
// located and found, a link lost and regained, an alarm raised, acknowledged and cleared, a map
// error flagged, an incident-command failover; and the same file cut short.
#include "mission_record.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>

#include "report_geojson.hpp"
#include "report_html.hpp"
#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/idl_schemas.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/topic_catalog.hpp"
#include "sarloc/dds/topics.hpp"
#include "sarloc/recording/mcap_writer.hpp"
#include "support/sample_messages.hpp"

namespace sarloc::report {
namespace {

namespace fs = std::filesystem;
constexpr std::int64_t kEpoch = 1'800'000'000'000'000'000LL;
constexpr std::int64_t kSec = 1'000'000'000LL;

const std::string kMissionYaml =
    "victims:\n  - {name: A, position: [10.0, 20.0, -1.0]}\n"
    "rescuers:\n  - {id: r1, team: north}\n  - {id: ff1, team: alpha, role: firefighter}\n";

class Recording {
 public:
  explicit Recording(const std::string& path, const std::string& mission_yaml = kMissionYaml) : writer_(path, {}) {
    writer_.write_metadata({"sarloc.recording",
                            {{"mission", "synthetic"},
                             {"epoch_ns", std::to_string(kEpoch)},
                             {"speedup", "1"},
                             {"mission_yaml", mission_yaml}}});
    for (const auto& topic : dds::topic_catalog()) {
      const auto schema = writer_.add_schema(topic.type_name, "omgidl", dds::self_contained_idl(topic.idl_file));
      channels_[topic.name] = writer_.add_channel(topic.name, schema, "cdr", {});
    }
    channels_["sarloc/recorder_events"] = writer_.add_channel("sarloc/recorder_events", 0, "json", {});
  }
  template <class T>
  void write(const T& idl, std::int64_t at_ns, std::uint32_t sequence = 0) {
    const auto bytes = dds::encode_payload<typename dds::TopicTraits<T>::PubSubType>(idl);
    ASSERT_FALSE(bytes.empty());
    writer_.write(channels_.at(dds::TopicTraits<T>::kName), sequence, static_cast<std::uint64_t>(at_ns),
                  static_cast<std::uint64_t>(at_ns), bytes.data(), bytes.size());
  }
  void write_json(const std::string& topic, const std::string& text, std::int64_t at_ns) {
    writer_.write(channels_.at(topic), 0, static_cast<std::uint64_t>(at_ns), static_cast<std::uint64_t>(at_ns),
                  reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  }
  void write_garbage(const std::string& topic, std::int64_t at_ns) {
    const std::uint8_t bytes[3] = {0, 1, 0};
    writer_.write(channels_.at(topic), 0, static_cast<std::uint64_t>(at_ns), static_cast<std::uint64_t>(at_ns), bytes, 3);
  }
  recording::McapWriter& writer() { return writer_; }

 private:
  recording::McapWriter writer_;
  std::map<std::string, std::uint16_t> channels_;
};

void write_mission(Recording& rec) {
  // A rescuer walking north, a victim located at 30 s and found at 40 s.
  for (int k = 0; k <= 50; ++k) {
    auto p = test::sample_responder_position();
    p.responder_id = "r1";
    p.team_id = "north";
    p.stamp = kEpoch + k * kSec;
    p.source = responder::PositionSource::kGnss;
    p.position.position = Vec3(10.0, 0.4 * k, 0.0);
    p.position.covariance = Mat3::Identity() * 0.01;
    p.converged = p.confirmed = p.map_error_suspected = false;
    rec.write(dds::to_idl(p), p.stamp);
  }
  for (int k = 20; k <= 50; k += 5) {
    auto v = test::sample_fused_victim();
    v.victim_id = 1;
    v.position.position = Vec3(10.3, 20.4, -1.0);
    v.position.covariance = Mat3::Identity() * 0.04;
    v.state = k < 30 ? incident::VictimState::kUnconfirmed : (k < 40 ? incident::VictimState::kLocated : incident::VictimState::kFound);
    v.located_at = k >= 30 ? kEpoch + 30 * kSec : 0;
    v.found_at = k >= 40 ? kEpoch + 40 * kSec : 0;
    v.last_update = kEpoch + k * kSec;
    v.first_seen = kEpoch + 20 * kSec;
    v.evidence_conflict = false;
    v.possibly_same_as = 0;
    rec.write(dds::to_idl(v), v.last_update);
  }
  // The incident frame's WGS-84 origin, as incident command publishes it.
  incident::IncidentFrame frame;
  frame.incident_id = "synthetic";
  frame.origin = {46.9480, 7.4474, 540.0};
  frame.established = kEpoch + 3 * kSec;
  rec.write(dds::to_idl(frame), kEpoch + 3 * kSec);
  // ff1's link: alive, lost at 12 s, alive again at 18 s.
  for (int k = 10; k <= 20; k += 2) {
    auto t = test::sample_team_status();
    t.team_id = "alpha";
    t.stamp = kEpoch + k * kSec;
    t.members.resize(1);
    t.members[0].responder_id = "ff1";
    t.members[0].link = (k >= 12 && k < 18) ? incident::LinkState::kLost : incident::LinkState::kAlive;
    t.members[0].accountability = (k >= 12 && k < 18) ? incident::AccountabilityState::kMissing : incident::AccountabilityState::kAccounted;
    rec.write(dds::to_idl(t), t.stamp);
  }
  // ff1 map-aided, with a map error suspected from 25 s to 27 s.
  for (int k = 20; k <= 30; ++k) {
    auto p = test::sample_responder_position();
    p.responder_id = "ff1";
    p.team_id = "";
    p.stamp = kEpoch + k * kSec;
    p.source = responder::PositionSource::kMapAided;
    p.map_error_suspected = k >= 25 && k < 27;
    rec.write(dds::to_idl(p), p.stamp);
  }
  // Then silent: the core daemon writes his last position again (estimator::PositionRefresh).
  {
    auto p = test::sample_responder_position();
    p.responder_id = "ff1";
    p.team_id = "";
    p.stamp = kEpoch + 30 * kSec;
    p.source = responder::PositionSource::kMapAided;
    p.map_error_suspected = false;
    for (int k = 40; k <= 50; k += 10) rec.write(dds::to_idl(p), kEpoch + k * kSec);
  }
  // A mayday raised at 21 s, acknowledged at 23 s, cleared at 25 s.
  auto alarm = test::sample_incident_alarm();
  alarm.alarm_id = 5;
  alarm.alarm.responder_id = "ff1";
  alarm.alarm.raised_at = kEpoch + 21 * kSec;
  alarm.alarm.active = true;
  alarm.alarm.cleared_at = 0;
  alarm.acknowledged = false;
  alarm.acknowledged_by.clear();
  alarm.acknowledged_at = 0;
  rec.write(dds::to_idl(alarm), kEpoch + 21 * kSec);
  alarm.acknowledged = true;
  alarm.acknowledged_by = "ic";
  alarm.acknowledged_at = kEpoch + 23 * kSec;
  rec.write(dds::to_idl(alarm), kEpoch + 23 * kSec);
  alarm.alarm.active = false;
  alarm.alarm.cleared_at = kEpoch + 25 * kSec;
  rec.write(dds::to_idl(alarm), kEpoch + 25 * kSec);
  // Incident command: node_status from two participants, the picture's writer changes at 33 s.
  auto status = [&](const std::string& node, std::int64_t at, std::uint32_t seq) {
    ::sarloc::NodeStatus n;
    n.node_id(node);
    n.kind(::sarloc::NODE_COMMAND);
    n.stamp(at);
    rec.write(n, at, seq);
  };
  rec.write_json("sarloc/recorder_events",
                 R"({"event":"writer_seen","topic":"sarloc/node_status","participant":"aaaa","sequence":1,"log_time_ns":)" +
                     std::to_string(kEpoch + 1 * kSec) + "}",
                 kEpoch + 1 * kSec);
  status("command-1", kEpoch + 1 * kSec, 1);
  rec.write_json("sarloc/recorder_events",
                 R"({"event":"writer_seen","topic":"sarloc/node_status","participant":"bbbb","sequence":1,"log_time_ns":)" +
                     std::to_string(kEpoch + 2 * kSec) + "}",
                 kEpoch + 2 * kSec);
  status("command-2", kEpoch + 2 * kSec, 1);
  rec.write_json("sarloc/recorder_events", R"({"event":"writer_seen","topic":"sarloc/incident_summary","participant":"aaaa","sequence":1,"log_time_ns":1})",
                 kEpoch + 3 * kSec);
  rec.write_json("sarloc/recorder_events", R"({"event":"writer_seen","topic":"sarloc/incident_summary","participant":"bbbb","sequence":1,"log_time_ns":2})",
                 kEpoch + 33 * kSec);
  rec.write_garbage("sarloc/fused_victim", kEpoch + 45 * kSec);
}

bool has_event(const MissionRecord& r, const std::string& kind, const std::string& text, double t_s) {
  for (const auto& e : r.events) {
    if (e.kind == kind && e.text.find(text) != std::string::npos && std::abs(e.t_s - t_s) < 0.01) return true;
  }
  return false;
}

TEST(MissionRecord, ReadsTracksVictimsAndEveryKindOfEventFromARecording) {
  const std::string path = (fs::temp_directory_path() / "sarloc_report_synthetic.mcap").string();
  {
    Recording rec(path);
    write_mission(rec);
    rec.writer().close();
  }
  const MissionRecord r = load_mission_record(path);
  EXPECT_TRUE(r.read.complete) << r.read.damage;
  EXPECT_EQ(r.mission_name, "synthetic");
  ASSERT_EQ(r.victims.size(), 1u);
  const auto& v = r.victims.at(1);
  ASSERT_TRUE(v.located_s && v.found_s);
  EXPECT_DOUBLE_EQ(*v.located_s, 30.0);
  EXPECT_DOUBLE_EQ(*v.found_s, 40.0);
  ASSERT_EQ(r.truth_victims.size(), 1u);
  EXPECT_NEAR((r.truth_victims[0].position - v.samples.back().position.position).norm(), 0.5, 1e-9);
  EXPECT_NEAR(radius95_2d(v.samples.back().position.covariance), std::sqrt(5.991464547107979 * 0.04), 1e-9);
  ASSERT_EQ(r.responders.at("r1").samples.size(), 51u);
  EXPECT_FALSE(r.responders.at("r1").firefighter);
  EXPECT_TRUE(r.responders.at("ff1").firefighter);
  EXPECT_EQ(r.responders.at("ff1").samples.size(), 11u) << "the daemon's copies of his last position are not points";
  EXPECT_TRUE(has_event(r, "victim", "victim 1 LOCATED", 30.0));
  EXPECT_TRUE(has_event(r, "victim", "victim 1 FOUND", 40.0));
  EXPECT_TRUE(has_event(r, "link", "ff1 (alpha): link LOST", 12.0));
  EXPECT_TRUE(has_event(r, "link", "regained", 18.0));
  EXPECT_TRUE(has_event(r, "accountability", "MISSING", 12.0));
  EXPECT_TRUE(has_event(r, "alarm", "MAYDAY alarm 5 for ff1 RAISED", 21.0));
  EXPECT_TRUE(has_event(r, "alarm", "acknowledged by ic", 23.0));
  EXPECT_TRUE(has_event(r, "alarm", "cleared", 25.0));
  EXPECT_TRUE(has_event(r, "map error", "suspects the floor plan", 25.0));
  EXPECT_TRUE(has_event(r, "map error", "no longer suspected", 27.0));
  EXPECT_TRUE(has_event(r, "command", "published by command-1", 3.0));
  EXPECT_TRUE(has_event(r, "command", "FAILOVER: incident picture now published by command-2", 33.0));
  EXPECT_EQ(r.quality.at("sarloc/fused_victim").undecodable, 1u);
  for (std::size_t k = 1; k < r.events.size(); ++k) EXPECT_LE(r.events[k - 1].t_s, r.events[k].t_s);

  // The HTML: self-contained (no script, no external reference) with its maps and tables.
  const std::string html = render_report(r);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("FAILOVER"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));
  EXPECT_EQ(html.find("https://"), std::string::npos);
  // The victim's latitude and longitude beside its ENU position, from the recorded origin.
  ASSERT_TRUE(r.incident_origin.has_value());
  const std::string wgs84 =
      incident::format_wgs84(incident::GeodeticFrame(*r.incident_origin).to_wgs84(Vec3(10.3, 20.4, -1.0)));
  EXPECT_EQ(wgs84.rfind("46.948", 0), 0u) << wgs84;
  EXPECT_NE(html.find("<td>" + wgs84 + "</td>"), std::string::npos) << wgs84;
  fs::remove(path);
}

// --geojson: the recorded mission's deposit (WGS-84 in the file) cut into the planner's strips,
// each with the share r1's walk covered; r1's track; the victim with its ellipse. In WGS-84
// about the recorded origin, read back to the incident frame here.
TEST(MissionRecord, ItsGeoJsonPlacesTheDepositStripsTracksAndVictimsOnTheEarth) {
  using Vec2 = Eigen::Vector2d;
  const GeodeticOrigin origin{46.9480, 7.4474, 540.0};  // write_mission's IncidentFrame
  const incident::GeodeticFrame frame(origin);
  // 80 m across, 120 m along the long axis (north); r1 starts at its south edge.
  const std::vector<Vec2> corners{{-30.0, 0.0}, {50.0, 0.0}, {50.0, 120.0}, {-30.0, 120.0}};
  std::string yaml =
      kMissionYaml + "incident:\n  latitude_deg: 46.9480\n  longitude_deg: 7.4474\n  altitude_m: 540\n  deposit:\n";
  for (const auto& c : corners) {
    const auto g = frame.to_wgs84(Vec3(c.x(), c.y(), 0.0));
    char line[120];
    std::snprintf(line, sizeof line, "    - {latitude_deg: %.9f, longitude_deg: %.9f}\n", g.latitude_deg,
                  g.longitude_deg);
    yaml += line;
  }
  const std::string path = (fs::temp_directory_path() / "sarloc_report_geojson.mcap").string();
  {
    Recording rec(path, yaml);
    write_mission(rec);
    rec.writer().close();
  }
  const MissionRecord r = load_mission_record(path);
  ASSERT_TRUE(r.deposit.has_value()) << (r.notes.empty() ? "" : r.notes.back());
  EXPECT_NEAR(r.deposit->area_m2(), 80.0 * 120.0, 0.5);
  const std::string html = render_report(r);
  EXPECT_NE(html.find("<polygon"), std::string::npos) << "the deposit on the report's avalanche map";
  EXPECT_NE(html.find("<h2>Search coverage</h2>"), std::string::npos);
  const nlohmann::json collection = render_geojson(r);
  ASSERT_EQ(collection["type"], "FeatureCollection");
  std::map<std::string, std::vector<nlohmann::json>> by_kind;
  for (const auto& f : collection["features"]) by_kind[f["properties"]["kind"]].push_back(f);
  const auto enu = [&](const nlohmann::json& position) {
    return frame.to_enu({position[1].get<double>(), position[0].get<double>(), origin.altitude_m});
  };
  ASSERT_EQ(by_kind["deposit"].size(), 1u);
  const auto& ring = by_kind["deposit"][0]["geometry"]["coordinates"][0];
  ASSERT_EQ(ring.size(), 5u) << "four corners, closed";
  EXPECT_EQ(ring.front(), ring.back());
  for (std::size_t k = 0; k < 4; ++k) {
    double nearest = 1e9;
    for (const auto& c : corners) nearest = std::min(nearest, (enu(ring[k]).head<2>() - c).norm());
    EXPECT_LT(nearest, 0.02) << ring[k];
  }
  // Two 40 m strips along the long axis, split at x = 10, where r1 walked from y = 0 to 20:
  // each has half of the 20 m reach around that walk (800 + 628 m^2) / 2 of its 4800 m^2.
  ASSERT_EQ(by_kind["strip"].size(), 2u);
  for (const auto& strip : by_kind["strip"]) {
    EXPECT_DOUBLE_EQ(strip["properties"]["width_m"].get<double>(), 40.0);
    EXPECT_NEAR(strip["properties"]["searched_fraction"].get<double>(), (800.0 + 200.0 * kPi) / 2.0 / 4800.0, 0.01)
        << strip;
  }
  ASSERT_EQ(by_kind["track"].size(), 2u) << "r1 and ff1";
  for (const auto& track : by_kind["track"]) {
    if (track["properties"]["responder_id"] != "r1") continue;
    ASSERT_EQ(track["geometry"]["type"], "LineString");
    ASSERT_EQ(track["geometry"]["coordinates"].size(), 51u);
    EXPECT_LT((enu(track["geometry"]["coordinates"][50]).head<2>() - Vec2(10.0, 20.0)).norm(), 0.02);
    EXPECT_EQ(track["properties"]["role"], "avalanche rescuer");
  }
  ASSERT_EQ(by_kind["victim"].size(), 1u);
  const auto& victim = by_kind["victim"][0];
  EXPECT_LT((enu(victim["geometry"]["coordinates"]).head<2>() - Vec2(10.3, 20.4)).norm(), 0.02);
  EXPECT_NEAR(victim["geometry"]["coordinates"][2].get<double>(), 539.0, 0.01) << "altitude: 1 m below the origin";
  EXPECT_EQ(victim["properties"]["state"], "FOUND");
  EXPECT_DOUBLE_EQ(victim["properties"]["found_s"].get<double>(), 40.0);
  EXPECT_EQ(victim["properties"]["found_utc"], "2027-01-15T08:00:40.000Z");
  ASSERT_EQ(by_kind["victim_ellipse_95"].size(), 1u);
  EXPECT_EQ(by_kind["victim_ellipse_95"][0]["geometry"]["coordinates"][0].size(), 37u);
  fs::remove(path);

  // No origin anywhere (no IncidentFrame, no mission file): nothing can be placed; said so.
  const std::string bare = (fs::temp_directory_path() / "sarloc_report_geojson_bare.mcap").string();
  {
    Recording rec(bare, "rescuers: []\n");
    auto p = test::sample_responder_position();
    rec.write(dds::to_idl(p), kEpoch);
    rec.writer().close();
  }
  try {
    render_geojson(load_mission_record(bare));
    ADD_FAILURE() << "a GeoJSON without an origin";
  } catch (const recording::RecordingError& e) {
    EXPECT_NE(std::string(e.what()).find("no WGS-84 origin"), std::string::npos) << e.what();
  }
  fs::remove(bare);
}

TEST(MissionRecord, ACutRecordingStillReportsWhatWasReadAndSaysWhatWasNot) {
  const std::string path = (fs::temp_directory_path() / "sarloc_report_cut.mcap").string();
  std::uint64_t flushed = 0;
  {
    Recording rec(path);
    write_mission(rec);
    rec.writer().flush();
    flushed = rec.writer().bytes_written();
    rec.writer().close();
  }
  fs::resize_file(path, flushed - 10);  // the last chunk's indexes, cut
  const MissionRecord r = load_mission_record(path);
  EXPECT_FALSE(r.read.complete);
  EXPECT_FALSE(r.read.damage.empty());
  EXPECT_EQ(r.victims.size(), 1u);  // the chunk itself was whole
  const std::string html = render_report(r);
  EXPECT_NE(html.find("This recording is damaged"), std::string::npos);
  fs::remove(path);
}

// A recording with incident command's search plan: the report's coverage is the plan's (its
// strips, their coverage and rescuers), and it shows who was sent to which victim and the dig
// order with its expected survivors, as the last recorded plan had them.
TEST(MissionRecord, ItsReportShowsTheRecordedPlansCoverageHandOversAndDigOrder) {
  const std::string path = (fs::temp_directory_path() / "sarloc_report_plan.mcap").string();
  {
    Recording rec(path);
    write_mission(rec);
    auto early = test::sample_search_plan();
    early.plan.searched = 0.1;
    early.digs = {};
    rec.write(dds::to_idl(early), kEpoch + 10 * kSec);
    rec.write(dds::to_idl(test::sample_search_plan()), kEpoch + 45 * kSec);
    rec.writer().close();
  }
  const MissionRecord r = load_mission_record(path);
  ASSERT_TRUE(r.search_plan.has_value());
  EXPECT_EQ(r.quality.at("sarloc/search_plan").undecodable, 0u);
  ASSERT_TRUE(r.deposit.has_value()) << "the deposit the plan covers, with none in the mission file";
  EXPECT_NEAR(r.deposit->area_m2(), 80.0 * 100.0, 1e-6);
  const std::string html = render_report(r);
  EXPECT_NE(html.find("<b>25.0 %</b> searched, as incident command's last recorded search plan had it"),
            std::string::npos)
      << "the last plan's 25 %, not the first's 10 %";
  EXPECT_NE(html.find("<td>50.0 %</td><td>r1</td>"), std::string::npos) << "strip 0: half searched, r1's";
  EXPECT_NE(html.find("victim 7 sent: r1"), std::string::npos);
  EXPECT_NE(html.find("expected survivors <b>1.35</b>"), std::string::npos);
  EXPECT_NE(html.find("<td>1</td><td>7</td><td>0.6</td>"), std::string::npos) << "victim 7 dug first";
  EXPECT_NE(html.find("<td>none free</td>"), std::string::npos) << "victim 9 waits for a digger";
  fs::remove(path);
}

}  // namespace
}  // namespace sarloc::report
