// What a whole mission leaves and shows: its recording read by independent readers, its report
// in Chromium, its inputs replayed into fresh nodes, and the live dashboard.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "mission_record.hpp"
#include "mission_runs.hpp"
#include "record_comparison.hpp"
#include "sarloc/core/incident/geodetic_frame.hpp"
#include "support/dds_test_domains.hpp"
#include "support/required_program.hpp"

namespace sarloc::test {
namespace {

// One feature as GDAL's ogrinfo printed it: its "kind" and its geometry as WKT.
struct OgrFeature {
  std::string kind, wkt;
};

std::vector<OgrFeature> ogr_features(const std::string& ogrinfo_text) {
  std::vector<OgrFeature> out;
  std::istringstream lines(ogrinfo_text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("OGRFeature(", 0) == 0) out.emplace_back();
    if (out.empty()) continue;
    if (line.rfind("  kind (String) = ", 0) == 0) out.back().kind = line.substr(18);
    for (const char* type : {"  POINT", "  LINESTRING", "  POLYGON"})
      if (line.rfind(type, 0) == 0) out.back().wkt = line.substr(2);
  }
  return out;
}

// The numbers of a WKT geometry as (longitude, latitude) pairs (a third, altitude, skipped).
std::vector<std::pair<double, double>> wkt_positions(const std::string& wkt) {
  std::vector<std::pair<double, double>> out;
  const bool has_z = wkt.find(" Z ") != std::string::npos;
  std::string numbers = wkt.substr(wkt.find('('));
  std::replace_if(
      numbers.begin(), numbers.end(), [](char c) { return c == '(' || c == ')' || c == ','; }, ' ');
  std::istringstream in(numbers);
  for (double lon, lat; in >> lon >> lat;) {
    out.emplace_back(lon, lat);
    if (has_z) in >> lon;
  }
  return out;
}

// sarloc-report --geojson on the mission's recording, read by an independent GIS reader (GDAL's
// ogrinfo): every feature there, the deposit where mixed.yaml puts it, each victim within 1.5 m
// of a true one once converted back into the incident frame.
void expect_geojson_reads_in_gdal(const std::string& recording, const fs::path& run_dir) {
  ASSERT_TRUE(sarloc::test::has_program("ogrinfo", "gdal-bin"));
  const fs::path geojson = run_dir / "mission.geojson";
  const int reported = std::system((std::string(SARLOC_BIN_DIR) + "/sarloc-report '" + recording + "' -o " +
                                    (run_dir / "report-geo.html").string() + " --geojson " + geojson.string() + " > " +
                                    (run_dir / "report-geo.out").string() + " 2>&1")
                                       .c_str());
  ASSERT_EQ(WEXITSTATUS(reported), 0) << file_text(run_dir / "report-geo.out");
  const json written = json::parse(file_text(geojson));
  const fs::path read = run_dir / "ogrinfo.txt";
  const int ogr =
      std::system(("ogrinfo -ro -al -geom=YES " + geojson.string() + " > " + read.string() + " 2>&1").c_str());
  const std::string text = file_text(read);
  ASSERT_EQ(WEXITSTATUS(ogr), 0) << text;
  EXPECT_NE(text.find("Feature Count: " + std::to_string(written["features"].size())), std::string::npos)
      << text.substr(0, 2000);
  EXPECT_NE(text.find("WGS 84"), std::string::npos) << "RFC 7946 GeoJSON is WGS-84: " << text.substr(0, 2000);
  const auto features = ogr_features(text);
  std::map<std::string, int> count;
  for (const auto& f : features) ++count[f.kind];
  EXPECT_EQ(count["deposit"], 1);
  EXPECT_GE(count["strip"], 2) << "60 m across at 40 m";
  EXPECT_EQ(count["track"], 4) << "r1, r2, ff1, ff2";
  EXPECT_EQ(count["victim"], 2);
  EXPECT_EQ(count["victim_ellipse_95"], 2);
  const incident::GeodeticFrame frame({46.5563, 7.9263, 2320.0});  // mixed.yaml's incident origin
  const auto enu = [&](const std::pair<double, double>& lon_lat) {
    return frame.to_enu({lon_lat.second, lon_lat.first, 2320.0}).head<2>().eval();
  };
  const std::vector<Eigen::Vector2d> corners{{-30.0, -5.0}, {30.0, -5.0}, {30.0, 70.0}, {-30.0, 70.0}};
  const std::vector<Eigen::Vector2d> victims{{-6.0, 35.0}, {3.0, 36.0}};
  for (const auto& f : features) {
    const auto positions = wkt_positions(f.wkt);
    ASSERT_FALSE(positions.empty()) << f.kind << ": " << f.wkt;
    const auto nearest = [&](const std::vector<Eigen::Vector2d>& to, const Eigen::Vector2d& p) {
      double d = 1e9;
      for (const auto& q : to) d = std::min(d, (p - q).norm());
      return d;
    };
    if (f.kind == "deposit") {
      EXPECT_EQ(positions.size(), 5u) << f.wkt;
      for (const auto& p : positions) EXPECT_LT(nearest(corners, enu(p)), 0.05) << f.wkt;
    }
    if (f.kind == "victim") {
      EXPECT_LT(nearest(victims, enu(positions[0])), 1.5) << f.wkt;
    }
  }
}

// The mission's recording, read by independent readers: the MCAP project's own reader with
// Foxglove's IDL decoder (every topic, the counts the recorder wrote, every CRC), then the
// report of it in headless Chromium (no console error, not blank).
TEST(Mission, ItsRecordingReadsInAnIndependentReaderAndItsReportOpensInChromium) {
  ASSERT_TRUE(sarloc::test::has_node());
  ASSERT_TRUE(sarloc::test::has_chromium());
  const auto run = run_mission("mixed.yaml", kDomainMissionRecorded);
  expect_complete(run);
  ASSERT_TRUE(run.summary.contains("recording")) << run_report(run);
  const std::string recording = run.summary["recording"];
  ASSERT_TRUE(fs::exists(recording)) << recording;

  const fs::path check = run.run_dir / "check.json";
  const int checked = std::system(("node " SARLOC_SOURCE_DIR "/tests/js/check_mcap.mjs '" + recording + "' > " + check.string()).c_str());
  std::ifstream check_in(check);
  const json report = json::parse(check_in);
  EXPECT_EQ(WEXITSTATUS(checked), 0) << report["errors"].dump();
  EXPECT_TRUE(report["errors"].empty()) << report["errors"].dump();
  const json& written = report["metadata"]["sarloc.recorder_counters"];
  for (const char* topic :
       {"sarloc/field_measurement", "sarloc/odometry", "sarloc/victim_estimate", "sarloc/guidance",
        "sarloc/responder_position", "sarloc/fused_victim", "sarloc/team_status", "sarloc/incident_summary",
        "sarloc/node_status", "sarloc/incident_frame", "sarloc/search_plan"}) {
    const json& channel = report["channels"][topic];
    EXPECT_GT(channel["count"].get<int>(), 0) << topic << " missing from the recording";
    EXPECT_EQ(channel["decodeFailures"], 0) << topic;
    // "received=N written=N lost=N rejected=..." as the recorder counted them.
    const std::string counted = written[topic];
    EXPECT_NE(counted.find("written=" + std::to_string(channel["count"].get<int>()) + " "), std::string::npos)
        << topic << ": " << counted << " vs " << channel["count"];
  }
  // The two victims found in the picture are FOUND in the last recorded fused_victim samples.
  EXPECT_EQ(report["channels"]["sarloc/fused_victim"]["last"]["state"], 2) << "VICTIM_FOUND";

  const fs::path html = run.run_dir / "report.html";
  const int reported = std::system((std::string(SARLOC_BIN_DIR) + "/sarloc-report '" + recording + "' -o " + html.string() +
                                    " > " + (run.run_dir / "report.out").string() + " 2>&1").c_str());
  ASSERT_EQ(WEXITSTATUS(reported), 0) << file_text(run.run_dir / "report.out");
  const std::string page = file_text(html);
  EXPECT_NE(page.find("Avalanche field"), std::string::npos);
  EXPECT_NE(page.find("Building, floor 0"), std::string::npos);
  EXPECT_NE(page.find("victim 1 FOUND"), std::string::npos);
  // The screenshot is kept as a test artifact beside the run's logs.
  const fs::path shot = run.run_dir / "report.png";
  const fs::path shot_json = run.run_dir / "screenshot.json";
  const int browsed = std::system(("node " SARLOC_SOURCE_DIR "/tests/js/screenshot.mjs " + html.string() + " " + shot.string() +
                                   " > " + shot_json.string() + " 2>&1").c_str());
  const std::string browser_said = file_text(shot_json);
  ASSERT_EQ(WEXITSTATUS(browsed), 0) << browser_said;
  const json shot_report = json::parse(browser_said);
  EXPECT_TRUE(shot_report["errors"].empty()) << browser_said;
  EXPECT_GE(shot_report["svgs"].get<int>(), 3) << "two maps and the timeline";
  EXPECT_GT(shot_report["inkFraction"].get<double>(), 0.01) << "blank screenshot: " << browser_said;
  EXPECT_GT(shot_report["colours"].get<int>(), 20) << browser_said;
  expect_geojson_reads_in_gdal(recording, run.run_dir);

  // The same recording on the dashboard's debrief view: the timeline scrubs and plays.
  const fs::path url_file = run.run_dir / "replay.url";
  const std::string dashboard = std::string(SARLOC_BIN_DIR) + "/sarloc-dashboard -c " + SARLOC_MISSION_DIR +
                                "/mixed.yaml --recording '" + recording + "' --port 0 --url-file " + url_file.string() +
                                " --log-level warn > " + (run.run_dir / "dashboard-replay.log").string() + " 2>&1 & echo $!";
  FILE* spawned = ::popen(dashboard.c_str(), "r");
  char pid_text[32] = {0};
  ASSERT_NE(std::fgets(pid_text, sizeof pid_text, spawned), nullptr);
  ::pclose(spawned);
  const int dashboard_pid = std::atoi(pid_text);
  for (int k = 0; k < 100 && (!fs::exists(url_file) || fs::file_size(url_file) == 0); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::string url;
  std::getline(std::ifstream(url_file), url);
  const fs::path replay_out = run.run_dir / "dashboard-replay.json";
  const int replayed = std::system(("node " SARLOC_SOURCE_DIR "/tests/js/dashboard_replay.mjs '" + url + "' " + run.run_dir.string() +
                                    " > " + replay_out.string() + " 2>&1").c_str());
  ::kill(dashboard_pid, SIGTERM);
  const std::string replay_said = file_text(replay_out);
  ASSERT_EQ(WEXITSTATUS(replayed), 0) << replay_said << file_text(run.run_dir / "dashboard-replay.log");
  const json replay = json::parse(replay_said);
  EXPECT_TRUE(replay["errors"].empty()) << replay_said;
  EXPECT_EQ(replay["atEnd"], json::array({"FOUND", "FOUND"})) << replay_said;
  // mixed.yaml's 60 m deposit: incident command's plan of two strips, on the map with labels.
  EXPECT_EQ(replay["stripsAtEnd"], 2) << replay_said;
  EXPECT_EQ(replay["stripLabels"].size(), 2U) << replay_said;
  // Both FOUND victims in the plan's dig order, with its expected survivors.
  EXPECT_EQ(replay["digsAtEnd"].size(), 2U) << replay_said;
  EXPECT_NE(replay["digSurvivors"], "—") << replay_said;
  EXPECT_TRUE(replay["atStart"].empty()) << "no victim at the recording's start: " << replay_said;
  EXPECT_GT(replay["advancedS"].get<double>(), 5.0) << "playing moves the timeline: " << replay_said;
}

// Replaying only what the devices measured into a fresh core daemon and incident command gives
// the recorded outcome again (report::reproduction_failures defines "again"); with another
// configuration, the comparison shows the difference.
TEST(Mission, ReplayingItsInputsIntoFreshNodesReproducesTheRecordedPicture) {
  const auto run = run_mission("mixed.yaml", kDomainMissionReplay);
  expect_complete(run);
  const std::string recording = run.summary["recording"];
  const std::string domain = std::to_string(static_cast<int>(kDomainMissionReplay));
  auto replay = [&](const std::string& config, const std::string& name) {
    const fs::path out = run.run_dir / (name + ".mcap");
    const std::string command = std::string(SARLOC_BIN_DIR) + "/sarloc-replay '" + recording + "' -c " + config +
                                " --domain " + domain + " --inputs-only --run-nodes --record " + out.string() + " --run-dir " +
                                (run.run_dir / name).string() + " --log-level warn > " + (run.run_dir / (name + ".out")).string() +
                                " 2>&1";
    const int status = std::system(command.c_str());
    EXPECT_EQ(WEXITSTATUS(status), 0) << file_text(run.run_dir / (name + ".out"));
    return sarloc::report::load_mission_record(out.string());
  };
  const auto original = sarloc::report::load_mission_record(recording);
  const auto again = replay(std::string(SARLOC_MISSION_DIR) + "/mixed.yaml", "replay");
  const auto comparison = sarloc::report::compare_records(again, original);
  const auto failures = sarloc::report::reproduction_failures(comparison);
  std::string said;
  for (const auto& f : failures) said += f + "\n";
  EXPECT_TRUE(failures.empty()) << said;
  ASSERT_EQ(comparison.victims.size(), 2U);
  for (const auto& p : comparison.victims) EXPECT_EQ(p.state_here, sarloc::incident::VictimState::kFound);
  ASSERT_EQ(comparison.tracks.size(), 2U) << "both firefighters' map-aided tracks";
  for (const auto& t : comparison.tracks) EXPECT_GT(t.matched, 50U) << t.responder;

  // Another configuration: fewer particles for the firefighters. Same inputs, other tracks.
  std::string text = file_text(std::string(SARLOC_MISSION_DIR) + "/mixed.yaml");
  const std::string relative = "../../../config/buildings/house-125.yaml";
  text.replace(text.find(relative), relative.size(), std::string(SARLOC_SOURCE_DIR) + "/config/buildings/house-125.yaml");
  text += "firefighter: {filter: {particles: 500, particles_max: 500}}\n";
  const fs::path changed = run.run_dir / "changed.yaml";
  std::ofstream(changed) << text;
  const auto other = replay(changed.string(), "changed");
  const auto difference = sarloc::report::compare_records(other, original);
  double largest = 0.0;
  for (const auto& t : difference.tracks) largest = std::max(largest, t.rms_m);
  EXPECT_GT(largest, 0.0) << "another particle count must give other map-aided fixes";
}

// The dashboard in headless Chromium while a mission runs: loads with no console error, shows
// the aggregator's victims and their states changing live (no reload), a killed firefighter's
// link lost, and an alarm acknowledged with the token (refused without it).
TEST(Mission, TheDashboardShowsTheMissionLiveInABrowser) {
  ASSERT_TRUE(sarloc::test::has_node());
  ASSERT_TRUE(sarloc::test::has_chromium());
  const fs::path run_dir = fs::temp_directory_path() / "sarloc-mission-test-dashboard";
  fs::remove_all(run_dir);
  fs::create_directories(run_dir);
  const std::string mission = std::string(SARLOC_BIN_DIR) + "/sarloc-mission " + SARLOC_MISSION_DIR + "/dashboard.yaml --domain " +
                              std::to_string(static_cast<int>(kDomainMissionDashboard)) + " --run-dir " + run_dir.string() +
                              " --json " + (run_dir / "summary.json").string() +
                              " --no-record --dashboard --dashboard-port 0 --kill ff1@30 --log-level info > " +
                              (run_dir / "mission.out").string() + " 2>&1";
  std::thread runner([&] { std::system(mission.c_str()); });
  const fs::path url_file = run_dir / "dashboard.url";
  for (int k = 0; k < 150 && (!fs::exists(url_file) || fs::file_size(url_file) == 0); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::string url, feed;
  {
    std::ifstream lines(url_file);
    std::getline(lines, url);
    std::getline(lines, feed);
  }
  ASSERT_FALSE(url.empty()) << file_text(run_dir / "mission.out");
  ASSERT_FALSE(feed.empty()) << "no Foxglove feed: " << file_text(run_dir / "mission.out");
  // Meanwhile, a Foxglove client on the feed.
  const fs::path feed_out = run_dir / "foxglove.json";
  std::thread foxglove([&] {
    std::system(("node --experimental-websocket " SARLOC_SOURCE_DIR "/tests/js/foxglove_feed.mjs " + feed + " 18 > " +
                 feed_out.string() + " 2>&1").c_str());
  });
  const fs::path browser_out = run_dir / "browser.json";
  const int browsed = std::system(("node " SARLOC_SOURCE_DIR "/tests/js/dashboard_e2e.mjs '" + url + "' " + run_dir.string() +
                                   " ff1 > " + browser_out.string() + " 2>&1").c_str());
  foxglove.join();
  runner.join();
  // The token is for whoever started the mission: in a file only its owner reads, never in a log.
  EXPECT_EQ(fs::status(url_file).permissions() & (fs::perms::group_all | fs::perms::others_all), fs::perms::none)
      << "dashboard.url holds the token";
  const std::string token = url.substr(url.find("#token=") + 7);
  ASSERT_GE(token.size(), 8U) << url;
  EXPECT_NE(file_text(run_dir / "dashboard.log").find("operator token is in"), std::string::npos);
  EXPECT_EQ(file_text(run_dir / "dashboard.log").find(token), std::string::npos) << "the token is in the dashboard's log";
  const std::string fed = file_text(feed_out);
  const auto feed_start = fed.find("{\"errors\"");
  ASSERT_NE(feed_start, std::string::npos) << fed;
  const json feed_report = json::parse(fed.substr(feed_start));
  EXPECT_TRUE(feed_report["errors"].empty()) << fed;
  EXPECT_EQ(feed_report["subprotocol"], "foxglove.websocket.v1");
  for (const char* topic : {"sarloc/fused_victim", "sarloc/team_status", "sarloc/responder_position", "sarloc/field_measurement"}) {
    const json& channel = feed_report["channels"][topic];
    EXPECT_EQ(channel["schemaEncoding"], "omgidl") << topic;
    EXPECT_EQ(channel["encoding"], "cdr") << topic;
    EXPECT_GT(channel["count"].get<int>(), 0) << topic << ": " << fed.substr(0, 2000);
    EXPECT_EQ(channel["decodeFailures"], 0) << topic;
  }
  EXPECT_GT(feed_report["channels"]["sarloc/fused_victim"].value("last", json::object()).value("victim_id", 0), 0) << fed.substr(0, 2000);
  EXPECT_GE(feed_report["channels"]["sarloc/team_status"].value("last", json::object()).value("members", json::array()).size(), 2U);
  const std::string said = file_text(browser_out);
  ASSERT_EQ(WEXITSTATUS(browsed), 0) << said;
  const json browser = json::parse(said);
  std::ifstream summary_in(run_dir / "summary.json");
  ASSERT_TRUE(summary_in) << file_text(run_dir / "mission.out");
  const json summary = json::parse(summary_in);
  EXPECT_TRUE(browser["errors"].empty()) << said;
  EXPECT_EQ(browser["victimCount"], summary["fused_victim_count"]) << "the page shows the aggregator's victims";
  bool changed_live = false;
  for (const auto& [id, states] : browser["statesSeen"].items()) changed_live = changed_live || states.size() >= 2;
  EXPECT_TRUE(changed_live) << "a victim's state changed on the page without a reload: " << browser["statesSeen"].dump();
  EXPECT_TRUE(browser["linkLostSeen"]) << said;
  EXPECT_EQ(browser["ackRefusedStatus"], 401) << said;
  EXPECT_TRUE(browser["ackAccepted"]) << said;
  // The test mission runs without DDS Security: the header must say so, in red.
  EXPECT_EQ(browser["ddsTrust"]["className"], "alarm") << said;
  EXPECT_NE(browser["ddsTrust"]["text"].get<std::string>().find("NOT AUTHENTICATED"), std::string::npos) << said;
  EXPECT_EQ(browser["csp"].get<std::string>().rfind("default-src 'self'", 0), 0U) << said;
  EXPECT_EQ(browser["addressBar"].get<std::string>().find("token"), std::string::npos) << "the token stayed in the address bar: " << said;
  const json& glance = browser["glance"];
  EXPECT_TRUE(glance["labelOverlaps"].empty()) << "map labels overlap: " << glance.dump();
  ASSERT_FALSE(glance["teamHeaders"].empty()) << said;
  for (const auto& headers : glance["teamHeaders"])
    EXPECT_EQ(headers.get<int>(), 6) << "a team table without its column headers";
  // How sure each member's position is, in words (issue 65): the firefighters' map-aided ones
  // from a reported entry are placed or not yet, never anything else.
  for (const char* firefighter : {"ff1", "ff2"}) {
    ASSERT_TRUE(glance["positionCells"].contains(firefighter)) << said;
    const std::string cell = glance["positionCells"][firefighter];
    EXPECT_TRUE(cell.rfind("confirmed", 0) == 0 || cell.rfind("converged", 0) == 0 ||
                cell.rfind("not yet placed", 0) == 0 || cell.rfind("one of ", 0) == 0 || cell == "dead reckoning")
        << firefighter << ": '" << cell << "'";
  }
  ASSERT_FALSE(glance["foundCells"].empty()) << said;
  for (const auto& cell : glance["foundCells"]) EXPECT_EQ(cell.get<std::string>().rfind("at T+", 0), 0U) << "a FOUND victim without its time: " << cell;
  EXPECT_EQ(glance["incident"], "test-incident") << "the header names the incident";
  EXPECT_NE(glance["wall"].get<std::string>().find(':'), std::string::npos) << "the header shows the wall-clock time";
  EXPECT_EQ(glance["legendItems"], 12)
      << "nine symbols (dug out, a firefighter not yet placed and one of an ambiguous one's "
         "places too), the avalanche deposit, a deposit being drawn and a search strip";
  EXPECT_EQ(glance["areas"], 3) << "everything, the avalanche field, the house 80 m east: " << glance.dump();
  ASSERT_FALSE(browser["labelHeightsPx"].empty()) << said;
  for (const auto& height : browser["labelHeightsPx"]) {
    EXPECT_GT(height.get<double>(), 6.0) << "a map label too small to read: " << said;
    EXPECT_LT(height.get<double>(), 24.0) << "a map label drawn huge: " << said;
  }
  EXPECT_TRUE(fs::exists(run_dir / "dashboard.png"));
  std::printf("dashboard in Chromium: render median %.2f ms, p95 %.2f ms (%d frames); push latency p50 %.0f ms, p99 %.0f ms\n",
              browser["frameMs"]["median"].get<double>(), browser["frameMs"]["p95"].get<double>(), browser["frameMs"]["count"].get<int>(),
              browser["pushLatencyMs"]["p50"].get<double>(), browser["pushLatencyMs"]["p99"].get<double>());
}

}  // namespace
}  // namespace sarloc::test
