#pragma once
// The mission tests' runs: sarloc-mission started on a test mission (or under a UDP fault in a
// namespace of its own), its summary, and the checks most tests share.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

namespace sarloc::test {

namespace fs = std::filesystem;
using nlohmann::json;

struct MissionRun {
  int exit_code = -1;
  json summary;
  fs::path run_dir;
};

inline MissionRun run_mission(const std::string& mission_file, std::uint32_t domain, const std::string& extra = "",
                       const std::string& prefix = "") {
  MissionRun run;
  run.run_dir = fs::temp_directory_path() / ("sarloc-mission-test-" + std::to_string(domain));
  fs::remove_all(run.run_dir);
  fs::create_directories(run.run_dir);
  const fs::path json_path = run.run_dir / "summary.json";
  // A bare name is one of this folder's test missions; an absolute path any other.
  const std::string path = mission_file.front() == '/' ? mission_file : std::string(SARLOC_MISSION_DIR) + "/" + mission_file;
  // Recordings go with the run's other files, never into the build tree.
  const std::string record = extra.find("-record") == std::string::npos ? " --record " + (run.run_dir / "recordings").string() : "";
  const std::string command = prefix + std::string(SARLOC_BIN_DIR) + "/sarloc-mission " + path + " --domain " + std::to_string(domain) + " --run-dir " +
                              run.run_dir.string() + " --json " + json_path.string() + record + " " +
                              (extra.find("--log-level") == std::string::npos ? "--log-level warn " : "") + extra +
                              " > " + (run.run_dir / "mission.out").string() + " 2>&1";
  const int status = std::system(command.c_str());
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(json_path);
  if (in) run.summary = json::parse(in);
  return run;
}

inline std::string file_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// What a failed run said: its output and the logs of incident command and the core daemon (the
// rescuers' log every epoch), so that a failure seen only in CI can be traced from CI's output.
inline std::string run_report(const MissionRun& run) {
  std::string report = file_text(run.run_dir / "mission.out");
  std::vector<fs::path> logs;
  for (const auto& entry : fs::directory_iterator(run.run_dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".log" && (name.rfind("command", 0) == 0 || name.rfind("core", 0) == 0))
      logs.push_back(entry.path());
  }
  std::sort(logs.begin(), logs.end());
  for (const auto& log : logs) report += "\n--- " + log.filename().string() + "\n" + file_text(log);
  return report;
}

// Every victim found, exactly as many victims in the picture as were buried, and the finder's
// own estimate (what the diggers use) within 0.5 m. `max_incident_error_m` bounds the fused
// incident-frame error, which includes the finder's GNSS error. With `unconfirmed_contacts`
// the picture may also hold unconfirmed contacts (a signal a device still tracks, not located):
// only the confirmed victims must be exactly the buried ones. A withdrawn victim (unconfirmed,
// evidence conflict, no source: VictimFusion, "Withdrawal") is an honest contact either way, and
// so is an unconfirmed one the picture itself names as possibly a confirmed victim's transmitter
// (possibly_same_as: a twin, a repeat, or alike transmitter signatures).
inline void expect_complete(const MissionRun& run, double max_incident_error_m = 1.0, bool unconfirmed_contacts = false) {
  ASSERT_FALSE(run.summary.is_null()) << "no summary; see " << run.run_dir;
  EXPECT_EQ(run.exit_code, 0) << run_report(run);
  EXPECT_TRUE(run.summary["all_found"].get<bool>());
  std::set<std::uint32_t> confirmed_ids;
  for (const auto& f : run.summary["fused_victims"])
    if (f["confirmed"].get<bool>()) confirmed_ids.insert(f["victim_id"].get<std::uint32_t>());
  std::size_t counted = 0;
  for (const auto& f : run.summary["fused_victims"]) {
    const bool confirmed = f["confirmed"].get<bool>();
    const bool withdrawn = !confirmed && f["evidence_conflict"].get<bool>() && f["sources"] == 0;
    const bool names_a_confirmed_one =
        !confirmed && confirmed_ids.count(f["possibly_same_as"].get<std::uint32_t>()) != 0;
    if (unconfirmed_contacts ? confirmed : !withdrawn && !names_a_confirmed_one) ++counted;
  }
  EXPECT_EQ(counted, run.summary["true_victim_count"].get<std::size_t>())
      << "duplicates or misses: " << run.summary["fused_victims"].dump() << "\n"
      << run_report(run);
  for (const auto& v : run.summary["victims"]) {
    EXPECT_TRUE(v["found"].get<bool>()) << v.dump();
    ASSERT_FALSE(v["error_m"].is_null()) << v.dump();
    EXPECT_LE(v["error_m"].get<double>(), max_incident_error_m) << v.dump();
    ASSERT_FALSE(v["relative_error_m"].is_null()) << v.dump();
    EXPECT_LE(v["relative_error_m"].get<double>(), 0.5) << v.dump();
    EXPECT_FALSE(v["time_to_locate_s"].is_null()) << v.dump();
  }
  // Every victim FOUND in the picture has its FOUND time and a survival at its dig-out (the
  // survival curve, docs/operations/search-planning.md); the expected survivors sum them.
  double survivors = 0.0;
  for (const auto& v : run.summary["victims"]) {
    if (!v["found"].get<bool>()) continue;
    ASSERT_FALSE(v["found_at_s"].is_null()) << v.dump();
    ASSERT_FALSE(v["survival"].is_null()) << v.dump();
    EXPECT_GE(v["found_at_s"].get<double>(), v["time_to_locate_s"].get<double>()) << v.dump();
    EXPECT_GT(v["survival"].get<double>(), 0.0) << v.dump();
    EXPECT_LE(v["survival"].get<double>(), 1.0) << v.dump();
    survivors += v["survival"].get<double>();
  }
  if (!run.summary["victims"].empty()) {
    ASSERT_FALSE(run.summary["expected_survivors"].is_null()) << run.summary.dump();
    EXPECT_NEAR(run.summary["expected_survivors"].get<double>(), survivors, 1e-9);
  }
}

// A mission over the UDP-only profile inside a namespace of its own that degrades every UDP
// datagram on loopback (`fault`: ISOLATED_UDP_LOSS=P or ISOLATED_UDP_OUTAGE=UP:DOWN).
inline MissionRun run_degraded_mission(std::uint32_t domain, const std::string& fault) {
  const std::string isolated = std::string(SARLOC_SOURCE_DIR) + "/../shared/tools/isolated";
  if (!fs::exists(isolated)) return {};
  return run_mission("lossy.yaml", domain, "", "env -u SARLOC_ISOLATED " + fault + " " + isolated + " ");
}

// Under faults: every victim found by a finder, and no victim of the picture confirmed
// (LOCATED / FOUND) that is not a buried one; an UNCONFIRMED hypothesis may still be open.
inline void expect_found_without_ghosts(const MissionRun& run) {
  ASSERT_FALSE(run.summary.is_null()) << file_text(run.run_dir / "mission.out");
  EXPECT_EQ(run.exit_code, 0) << file_text(run.run_dir / "mission.out");
  for (const auto& v : run.summary["victims"]) {
    EXPECT_TRUE(v["found"].get<bool>()) << v.dump();
    ASSERT_FALSE(v["error_m"].is_null()) << v.dump();
    EXPECT_LE(v["error_m"].get<double>(), 1.0) << v.dump();
    EXPECT_EQ(v.value("false_found", 0), 0) << "a finder's FOUND outside its stated radius: " << v.dump();
  }
  for (const auto& f : run.summary["fused_victims"]) {
    if (f["confirmed"].get<bool>()) {
      EXPECT_TRUE(f["matches_a_buried_victim"].get<bool>()) << "confirmed ghost: " << f.dump();
    }
  }
  EXPECT_EQ(run.summary["confirmed_fused_victim_count"], run.summary["true_victim_count"]);
}

}  // namespace sarloc::test
