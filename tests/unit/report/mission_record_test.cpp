// The report's reading of a recording, on a recording made here with known content: victims
// located and found, a link lost and regained, an alarm raised, acknowledged and cleared, a map
// error flagged, an incident-command failover; and the same file cut short.
#include "mission_record.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "report_html.hpp"
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

class Recording {
 public:
  explicit Recording(const std::string& path) : writer_(path, {}) {
    writer_.write_metadata({"sarloc.recording",
                            {{"mission", "synthetic"},
                             {"epoch_ns", std::to_string(kEpoch)},
                             {"speedup", "1"},
                             {"mission_yaml", "victims:\n  - {name: A, position: [10.0, 20.0, -1.0]}\n"
                                              "rescuers:\n  - {id: r1, team: north}\n  - {id: ff1, team: alpha, role: firefighter}\n"}}});
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
  EXPECT_TRUE(has_event(r, "victim", "victim 1 LOCATED", 30.0));
  EXPECT_TRUE(has_event(r, "victim", "victim 1 FOUND", 40.0));
  EXPECT_TRUE(has_event(r, "link", "ff1 (alpha): link LOST", 12.0));
  EXPECT_TRUE(has_event(r, "link", "regained", 18.0));
  EXPECT_TRUE(has_event(r, "accountability", "MISSING", 12.0));
  EXPECT_TRUE(has_event(r, "alarm", "MAYDAY alarm 5 for ff1 raised", 21.0));
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

}  // namespace
}  // namespace sarloc::report
