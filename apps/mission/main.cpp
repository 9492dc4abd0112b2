// sarloc-mission: sarloc's main job. Starts the core daemon(s), one sarloc-rescuer process per
// rescuer and command.instances sarloc-command processes (one active, the others standing by)
// as separate processes over DDS, watches the incident picture like a dashboard would, stops
// everything when every victim is found or the time limit passes, and prints the summary.
// Exit 0 only when every victim was found.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "sarloc/app/command_line.hpp"
#include "sarloc/app/child_process.hpp"
#include "sarloc/app/json_io.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/mission_config.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shipped_missions.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/mission/mission_summary.hpp"
#include "sarloc/core/mission/victim_matching.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/recorder.hpp"

namespace {

using namespace sarloc;
namespace fs = std::filesystem;

struct Fault {
  bool restart = false;  ///< --restart (start again what an earlier --kill stopped) instead of --kill
  std::string target;  ///< "core", "command" (the active instance) or a rescuer id
  double at_s = 0.0;   ///< mission seconds
  bool done = false;
  std::chrono::steady_clock::time_point when{};
  double link_lost_after_s = -1.0;  ///< rescuer faults: wall seconds until command reported it lost
  // Incident-command faults.
  unsigned instance = 0;               ///< which sarloc-command instance (1..)
  std::string killed_participant;      ///< its DDS participant (GUID prefix), if known
  double handover_after_s = -1.0;      ///< wall seconds until another instance's picture arrived
  std::string taken_over_by;           ///< that instance's node id
  std::vector<incident::FusedVictim> picture_at_kill;
};

Fault parse_fault(const std::string& text, bool restart) {
  const std::string option = restart ? "--restart" : "--kill";
  const auto at = text.rfind('@');
  if (at == std::string::npos || at == 0) throw ConfigError(option + " = '" + text + "': expected TARGET@SECONDS");
  Fault f;
  f.restart = restart;
  f.target = text.substr(0, at);
  try {
    f.at_s = std::stod(text.substr(at + 1));
  } catch (const std::exception&) {
    throw ConfigError(option + " = '" + text + "': '" + text.substr(at + 1) + "' is not a number of seconds");
  }
  if (!(f.at_s >= 0.0)) throw ConfigError(option + " = '" + text + "': time must be >= 0");
  if (restart && f.target != "core" && f.target != "command") {
    throw ConfigError(option + " = '" + text + "': only core or command can be restarted");
  }
  return f;
}

// "NAME=HOST" of each --host (CLI11 reads a map option as key/value token pairs, not as NAME=HOST).
std::map<std::string, std::string> parse_hosts(const std::vector<std::string>& items) {
  std::map<std::string, std::string> hosts;
  for (const auto& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) throw ConfigError("--host " + item + ": expected NAME=HOST");
    hosts[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return hosts;
}

// --host NAME=HOST needs a --launcher and a process of that name in this mission.
void check_placement(const app::MissionConfig& mission, const std::map<std::string, std::string>& hosts,
                     const std::string& launcher) {
  if (hosts.empty()) return;
  if (launcher.empty()) throw ConfigError("--host given without --launcher: nothing can start a process on a host");
  std::set<std::string> names;
  if (mission.sectors.empty()) names.insert("core");
  for (const auto& sector : mission.sectors) names.insert("core-" + sector);
  const unsigned instances = mission.command_instances();
  for (unsigned k = 1; k <= instances; ++k) names.insert(instances == 1 ? "command" : "command-" + std::to_string(k));
  for (const auto& r : mission.scenario.rescuers) names.insert("rescuer-" + r.id);
  for (const auto& f : mission.firefighters) names.insert("rescuer-" + f.id);
  for (const auto& [name, host] : hosts) {
    if (names.count(name) == 0) throw ConfigError("--host " + name + "=" + host + ": no process '" + name + "' in this mission");
    if (host.empty()) throw ConfigError("--host " + name + "=: empty host");
  }
}

// A fault that kills one rescuer's device (not a daemon, not incident command).
bool is_rescuer_kill(const Fault& f) { return f.target != "core" && f.target != "command"; }

// The incident picture as a late-joining dashboard sees it, and who publishes it.
struct Picture {
  std::mutex mutex;
  std::map<std::uint32_t, incident::FusedVictim> victims;
  std::map<std::string, incident::LinkState> links;
  std::vector<std::pair<eprosima::fastrtps::rtps::InstanceHandle_t, std::uint32_t>> instances;
  // The active incident command: the participant whose IncidentSummary arrives (exclusive
  // ownership: only the active instance's), and since when; NodeStatus names participants.
  std::string owner;
  std::chrono::steady_clock::time_point owner_since{}, owner_heard{};
  std::map<std::string, std::string> node_of_participant, participant_of_node;
  std::map<std::uint32_t, incident::IncidentAlarm> alarms;  ///< every alarm the picture held

  /// The fused victims now (copied, so matching runs without the lock).
  std::vector<incident::FusedVictim> victims_now() {
    std::lock_guard<std::mutex> lock(mutex);
    std::vector<incident::FusedVictim> out;
    for (const auto& [id, v] : victims) out.push_back(v);
    return out;
  }
};

std::string optional_text(const std::optional<double>& v, const char* format) {
  if (!v) return "-";
  char buf[32];
  std::snprintf(buf, sizeof(buf), format, *v);
  return buf;
}

std::string position_text(const Vec3& p) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "(%.1f, %.1f, %.1f)", p.x(), p.y(), p.z());
  return buf;
}

// "yes" (FOUND in the picture), "finder" (only its finders' devices know: no picture), "NO".
const char* found_text(const mission::VictimOutcome& v) {
  if (v.found) return "yes";
  return v.found_by_finder() ? "finder" : "NO";
}

std::string finders_text(const mission::VictimOutcome& v) {
  std::string out;
  for (const auto& id : v.finders) out += (out.empty() ? "" : ",") + id;
  return out.empty() ? "-" : out;
}

void print_summary(const mission::MissionSummary& s, const std::string& run_dir) {
  std::printf("\n%-10s %-26s %-26s %8s %10s %12s %6s  %s\n", "victim", "true position (E N U) m", "fused estimate m",
              "error m", "finder m", "located s", "found", "found by");
  for (const auto& v : s.victims) {
    std::printf("%-10s %-26s %-26s %8s %10s %12s %6s  %s\n", v.name.c_str(), position_text(v.true_position).c_str(),
                v.estimate ? position_text(*v.estimate).c_str() : "-", optional_text(v.error_m, "%.2f").c_str(),
                optional_text(v.relative_error_m, "%.2f").c_str(), optional_text(v.time_to_locate_s, "%.0f").c_str(),
                found_text(v), finders_text(v).c_str());
  }
  std::printf("\n%-10s %18s %10s %18s %22s\n", "rescuer", "distance walked m", "fallbacks", "guidance switches",
              "latency p50/p99 ms");
  for (const auto& id : s.rescuer_ids) {
    const auto it = s.devices.find(id);
    if (it == s.devices.end()) {
      std::printf("%-10s %18s\n", id.c_str(), "(no summary: killed?)");
      continue;
    }
    const auto& d = it->second;
    std::printf("%-10s %18.1f %10d %18d %10.1f / %-10.1f\n", id.c_str(), d.distance_walked_m, d.fallbacks,
                d.guidance_switches, d.latency_p50_ms.value_or(-1.0), d.latency_p99_ms.value_or(-1.0));
  }
  if (!s.firefighters.empty() || !s.firefighters_without_summary.empty()) {
    std::printf("\n%-11s %-6s %8s %7s %10s %12s %9s %11s %6s  %s\n", "firefighter", "team", "walked m", "floors",
                "converge s", "RMSE after m", "map err %", "confirmed %", "DR s", "alarms (delay from the true event)");
    for (const auto& f : s.firefighters) {
      std::string alarms;
      for (const auto& a : f.alarms) {
        char buf[128];
        std::snprintf(buf, sizeof(buf), "%s%s at %.1f s%s", alarms.empty() ? "" : "; ", a.kind.c_str(), a.raised_s,
                      a.delay_s ? (" (+" + optional_text(a.delay_s, "%.2f") + " s)").c_str() : "");
        alarms += buf;
        if (a.cleared_s) alarms += ", cleared at " + optional_text(a.cleared_s, "%.1f") + " s";
      }
      std::string floors;
      for (const auto floor : f.floors_visited) floors += (floors.empty() ? "" : ",") + std::to_string(floor);
      std::printf("%-11s %-6s %8.1f %7s %10s %12s %9.1f %11.1f %6.1f  %s\n", f.responder_id.c_str(), f.team.c_str(),
                  f.distance_walked_m, floors.c_str(), optional_text(f.time_to_converge_s, "%.1f").c_str(),
                  optional_text(f.rmse_after_convergence_m, "%.2f").c_str(), 100.0 * f.map_error_share,
                  100.0 * f.confirmed_share, f.dead_reckoning_s, alarms.empty() ? "-" : alarms.c_str());
    }
    for (const auto& id : s.firefighters_without_summary) std::printf("%-10s (no summary: killed?)\n", id.c_str());
    std::printf("\nalarms in the incident picture:");
    if (s.picture_alarms.empty()) std::printf(" none");
    for (const auto& a : s.picture_alarms) {
      std::printf("\n  %u %-10s %-8s raised at %.1f s%s", a.alarm_id, a.kind.c_str(), a.responder_id.c_str(), a.raised_s,
                  a.cleared_s ? (", cleared at " + optional_text(a.cleared_s, "%.1f") + " s").c_str() : "");
    }
    std::printf("\n");
  }
  if (!s.links_at_end.empty()) {
    std::printf("\nlinks in the incident picture at the end:");
    for (const auto& [id, link] : s.links_at_end) std::printf(" %s %s;", id.c_str(), link.c_str());
    std::printf("\n");
  }
  for (const auto& f : s.faults) {
    if (f.handover_after_s) {
      std::printf("\nincident command killed at mission second %.0f: %s took over after %.2f wall s\n", f.at_s,
                  f.taken_over_by.c_str(), *f.handover_after_s);
    }
  }
  if (!s.picture_available) {
    std::printf("\nNO INCIDENT PICTURE at the end (%s): \"found\" is what the picture knew before it was lost; "
                "\"found by\" is what the finders' devices know.\n",
                s.command_alive_at_end ? "no incident command published it" : "no incident command alive");
  }
  std::printf("\n%zu of %zu victims found in the incident picture, %zu by their finders; %zu in the picture; "
              "%.0f mission s in %.0f wall s. Logs: %s\n",
              s.found_count(), s.victims.size(), s.found_by_finder_count(), s.fused_victims.size(), s.mission_s,
              s.wall_s, run_dir.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-mission: a whole simulated mission (avalanche, building or both) over DDS on this machine"};
  std::string config_path = app::shipped_mission("default.yaml");
  std::string json_path;
  std::string run_dir;
  std::string log_level = "info";
  std::vector<std::string> kills;
  std::vector<std::string> restarts;
  double startup_s = 3.0;
  int domain = -1;
  std::string launcher;
  std::vector<std::string> host_args;  // NAME=HOST
  std::string record_dir;
  bool no_record = false;
  bool dashboard = false;
  int dashboard_port = -1;
  cli.add_option("mission", config_path, std::string("mission YAML (default: default.yaml in ") + app::kShippedMissionsHelp + ")");
  cli.add_option("--json", json_path, "write the summary as JSON here");
  cli.add_option("--run-dir", run_dir, "folder for the processes' logs and summaries (default: a new one in /tmp)");
  cli.add_option("--restart", restarts,
                 "start again what a --kill stopped (core: the daemon(s); command: the killed instance, which "
                 "rejoins as standby) at mission SECONDS, e.g. core@25");
  cli.add_option("--kill", kills,
                 "fault injection: SIGKILL TARGET (core, command = the active incident command, or a rescuer id) "
                 "at mission SECONDS, e.g. core@40");
  cli.add_option("--startup", startup_s, "wall seconds given to the processes to start and discover each other");
  cli.add_option("--domain", domain, "DDS domain id for every process, overriding dds.domain_id of the mission");
  cli.add_option("--launcher", launcher,
                 "command that runs a process on another host as LAUNCHER HOST PROGRAM ARGS... (e.g. lan-exec of "
                 "../shared/tools/lan; scripts/lan-mission)");
  cli.add_option("--host", host_args,
                 "run process NAME on HOST through --launcher: NAME is core (core-SECTOR), command (command-K with "
                 "several instances) or rescuer-ID, e.g. --host rescuer-r1=h5")
      ->delimiter(',');
  cli.add_option("--record", record_dir,
                 "folder for the mission's MCAP recording (default: record.directory of the mission, recordings/)");
  cli.add_flag("--no-record", no_record, "do not record the mission");
  cli.add_flag("--dashboard", dashboard, "also start sarloc-dashboard on the mission and print its URL");
  cli.add_option("--dashboard-port", dashboard_port, "the dashboard's port (default: dashboard.port of the mission; 0: any)");
  app::add_log_level_option(cli, log_level);
  cli.set_version_flag("--version", SARLOC_VERSION);
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-mission", [&]() -> app::ExitCode {
    app::setup_logging(log_level, "mission");
    const auto mission = app::load_mission_config(config_path);
    std::vector<Fault> faults;
    for (const auto& k : kills) {
      auto f = parse_fault(k, false);
      if (f.target != "core" && f.target != "command") (void)mission.team_of(f.target);  // known id?
      faults.push_back(f);
    }
    for (const auto& r : restarts) faults.push_back(parse_fault(r, true));
    const auto hosts = parse_hosts(host_args);  // process name -> host
    check_placement(mission, hosts, launcher);
    const fs::path bin_dir = fs::canonical("/proc/self/exe").parent_path();
    // scripts/demo builds only what a mission runs; the dashboard only with --dashboard.
    std::vector<std::string> started{"sarloc-core", "sarloc-rescuer", "sarloc-command", "sarloc-record"};
    if (dashboard) started.push_back("sarloc-dashboard");
    for (const auto& name : started) {
      if (!fs::exists(bin_dir / name)) {
        throw std::runtime_error(name + " is not in " + bin_dir.string() + ": build it first (scripts/build --target " + name + ")");
      }
    }
    if (run_dir.empty()) run_dir = (fs::temp_directory_path() / ("sarloc-mission-" + std::to_string(getpid()))).string();
    fs::create_directories(run_dir);
    const std::string config_abs = fs::absolute(config_path).string();
    spdlog::info("mission '{}': {} victims, {} rescuers, {} firefighters, speedup {}x; logs in {}", mission.name,
                 mission.scenario.victims.size(), mission.scenario.rescuers.size(), mission.firefighters.size(),
                 mission.speedup, run_dir);

    // The mission's own participant: it watches the picture like incident command's dashboard.
    const auto dds_config = app::participant_config(mission, domain, "sarloc-mission");
    const std::string domain_arg = std::to_string(dds_config.domain_id);
    auto participant = std::make_shared<sarloc::dds::Participant>(dds_config);
    Picture picture;
    sarloc::dds::ReaderEvents victim_events;
    victim_events.on_instance_gone = [&](const auto& info) {
      // A disposed victim was merged into another: drop it from the picture.
      if (info.instance_state != eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) return;
      std::lock_guard<std::mutex> lock(picture.mutex);
      for (const auto& [handle, id] : picture.instances) {
        if (handle == info.instance_handle) picture.victims.erase(id);
      }
    };
    sarloc::dds::Reader<::sarloc::FusedVictim> victim_reader(
        participant,
        [&](const ::sarloc::FusedVictim& v, const auto& info) {
          try {
            auto victim = sarloc::dds::to_core(v);
            std::lock_guard<std::mutex> lock(picture.mutex);
            picture.victims[v.victim_id()] = std::move(victim);
            auto& known = picture.instances;
            if (std::none_of(known.begin(), known.end(), [&](const auto& k) { return k.first == info.instance_handle; })) {
              known.emplace_back(info.instance_handle, v.victim_id());
            }
          } catch (const InputError& e) {
            spdlog::warn("ignoring a fused victim: {}", e.what());
          }
        },
        {}, victim_events);
    sarloc::dds::Reader<::sarloc::IncidentSummary> summary_reader(
        participant, [&](const ::sarloc::IncidentSummary&, const auto& info) {
          const std::string from = sarloc::dds::handle_text(info.publication_handle).substr(0, 24);
          const auto now = std::chrono::steady_clock::now();
          std::lock_guard<std::mutex> lock(picture.mutex);
          if (from != picture.owner) {
            picture.owner = from;
            picture.owner_since = now;
          }
          picture.owner_heard = now;
        });
    sarloc::dds::Reader<::sarloc::NodeStatus> status_reader(
        participant, [&](const ::sarloc::NodeStatus& n, const auto& info) {
          if (n.kind() != ::sarloc::NODE_COMMAND) return;
          const std::string from = sarloc::dds::handle_text(info.publication_handle).substr(0, 24);
          std::lock_guard<std::mutex> lock(picture.mutex);
          picture.node_of_participant[from] = n.node_id().to_string();
          picture.participant_of_node[n.node_id().to_string()] = from;
        });
    sarloc::dds::Reader<::sarloc::TeamStatus> team_reader(participant, [&](const ::sarloc::TeamStatus& t, const auto&) {
      try {
        const auto team = sarloc::dds::to_core(t);
        std::lock_guard<std::mutex> lock(picture.mutex);
        for (const auto& m : team.members) picture.links[m.responder_id] = m.link;
      } catch (const InputError& e) {
        spdlog::warn("ignoring a team status: {}", e.what());
      }
    });

    sarloc::dds::Reader<::sarloc::IncidentAlarm> alarm_reader(participant, [&](const ::sarloc::IncidentAlarm& a, const auto&) {
      try {
        auto alarm = sarloc::dds::to_core(a);
        std::lock_guard<std::mutex> lock(picture.mutex);
        picture.alarms[alarm.alarm_id] = std::move(alarm);
      } catch (const InputError& e) {
        spdlog::warn("ignoring an incident alarm: {}", e.what());
      }
    });

    // Mission time starts a little in the future so every process is up and discovered.
    const TimestampNs epoch = sarloc::dds::MissionClock::wall_now_ns() + static_cast<TimestampNs>(startup_s * 1e9);
    const sarloc::dds::MissionClock clock(epoch, mission.speedup);
    const std::string epoch_arg = std::to_string(epoch);
    auto log_file = [&](const std::string& name) { return (fs::path(run_dir) / (name + ".log")).string(); };
    // A process placed on a host (--host) starts through the launcher; the others here.
    auto placed = [&](const std::string& name, std::vector<std::string> args) {
      if (const auto it = hosts.find(name); it != hosts.end()) args.insert(args.begin(), {launcher, it->second});
      return args;
    };

    // The recorder first, so that it hears every process from its first sample.
    std::unique_ptr<app::ChildProcess> recorder;
    std::string recording_path;
    if (!no_record) {
      recording_path = fs::absolute(sarloc::dds::timestamped_recording_path(
                                        record_dir.empty() ? mission.record_directory : record_dir, mission.name))
                           .string();
      std::vector<std::string> args{(bin_dir / "sarloc-record").string(), "-c", config_abs, "--domain", domain_arg,
                                    "-o", recording_path, "--log-level", log_level,
                                    "--meta", "epoch_ns=" + epoch_arg,
                                    "--meta", "speedup=" + std::to_string(mission.speedup),
                                    "--meta-file", "mission_yaml=" + config_abs};
      if (!mission.building_path.empty()) args.insert(args.end(), {"--meta-file", "building_plan_yaml=" + mission.building_path});
      recorder = std::make_unique<app::ChildProcess>("record", args, log_file("record"));
      spdlog::info("recording the mission to {}", recording_path);
    }

    std::unique_ptr<app::ChildProcess> dashboard_process;
    if (dashboard) {
      const fs::path url_file = fs::path(run_dir) / "dashboard.url";
      fs::remove(url_file);
      std::vector<std::string> args{(bin_dir / "sarloc-dashboard").string(), "-c", config_abs, "--domain", domain_arg,
                                    "--epoch-ns", epoch_arg, "--url-file", url_file.string(), "--log-level", log_level};
      if (dashboard_port >= 0) args.insert(args.end(), {"--port", std::to_string(dashboard_port)});
      if (dashboard_port == 0) args.insert(args.end(), {"--foxglove-port", "0"});  // any free port for both
      dashboard_process = std::make_unique<app::ChildProcess>("dashboard", args, log_file("dashboard"));
      for (int k = 0; k < 50 && !fs::exists(url_file) && dashboard_process->running(); ++k) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      std::ifstream url(url_file);
      std::string text, feed;
      if (url && std::getline(url, text)) {
        std::printf("dashboard: %s\n", text.c_str());
        if (std::getline(url, feed) && !feed.empty()) std::printf("Foxglove / Lichtblick: %s\n", feed.c_str());
        std::fflush(stdout);
      } else {
        spdlog::error("the dashboard did not start: see {}", log_file("dashboard"));
      }
    }

    std::vector<std::unique_ptr<app::ChildProcess>> cores;
    std::vector<std::string> sectors = mission.sectors.empty() ? std::vector<std::string>{""} : mission.sectors;
    auto start_cores = [&](const std::string& suffix) {
      cores.clear();
      for (const auto& sector : sectors) {
        std::vector<std::string> args{(bin_dir / "sarloc-core").string(), "-c", config_abs, "--domain", domain_arg,
                                      "--log-level", log_level};
        if (!sector.empty()) args.insert(args.end(), {"--sector", sector});
        const std::string name = (sector.empty() ? "core" : "core-" + sector) + suffix;
        cores.push_back(std::make_unique<app::ChildProcess>(
            name, placed(sector.empty() ? "core" : "core-" + sector, args), log_file(name)));
      }
    };
    start_cores("");
    // Incident command: instance 1 claims the picture, the others stand by (command.instances).
    const unsigned instances = mission.command_instances();
    std::vector<std::unique_ptr<app::ChildProcess>> commands(instances);
    std::vector<bool> command_killed(instances, false);
    auto command_name = [&](unsigned k) { return instances == 1 ? std::string("command") : "command-" + std::to_string(k); };
    auto start_command = [&](unsigned k, const std::string& suffix) {
      const std::string name = command_name(k) + suffix;
      commands[k - 1] = std::make_unique<app::ChildProcess>(
          name,
          placed(command_name(k),
                 {(bin_dir / "sarloc-command").string(), "-c", config_abs, "--instance", std::to_string(k),
                  "--epoch-ns", epoch_arg, "--summary", (fs::path(run_dir) / (name + ".json")).string(), "--domain",
                  domain_arg, "--log-level", log_level}),
          log_file(name));
      command_killed[k - 1] = false;
    };
    for (unsigned k = 1; k <= instances; ++k) start_command(k, "");
    // The instance publishing the picture now (0: none heard yet).
    auto active_command = [&]() -> unsigned {
      std::lock_guard<std::mutex> lock(picture.mutex);
      const auto it = picture.node_of_participant.find(picture.owner);
      if (it == picture.node_of_participant.end()) return 0;
      for (unsigned k = 1; k <= instances; ++k) {
        if (mission.command_config(k).node_id == it->second) return k;
      }
      return 0;
    };
    std::map<std::string, std::unique_ptr<app::ChildProcess>> rescuers;
    for (const auto& r : mission.scenario.rescuers) {
      rescuers[r.id] = std::make_unique<app::ChildProcess>(
          "rescuer-" + r.id,
          placed("rescuer-" + r.id,
                 {(bin_dir / "sarloc-rescuer").string(), "-c", config_abs, "--id", r.id, "--epoch-ns", epoch_arg,
                  "--summary", (fs::path(run_dir) / (r.id + ".json")).string(), "--domain", domain_arg, "--log-level",
                  log_level}),
          log_file("rescuer-" + r.id));
    }
    // Firefighters' devices: the same app; each ends when its simulated search does.
    for (const auto& f : mission.firefighters) {
      rescuers[f.id] = std::make_unique<app::ChildProcess>(
          "rescuer-" + f.id,
          placed("rescuer-" + f.id,
                 {(bin_dir / "sarloc-rescuer").string(), "-c", config_abs, "--id", f.id, "--epoch-ns", epoch_arg,
                  "--summary", (fs::path(run_dir) / (f.id + ".json")).string(), "--domain", domain_arg, "--log-level",
                  log_level, "--quiet"}),
          log_file("rescuer-" + f.id));
    }

    const auto wall_start = std::chrono::steady_clock::now();
    bool interrupted = false;
    double mission_s = 0.0;
    while (true) {
      if (app::wait_for_shutdown(std::chrono::milliseconds(100))) {
        interrupted = true;
        break;
      }
      mission_s = static_cast<double>(clock.now() - epoch) / 1e9;
      for (auto& f : faults) {
        if (f.done || mission_s < f.at_s) continue;
        f.done = true;
        f.when = std::chrono::steady_clock::now();
        if (f.restart && f.target == "command") {
          // The instance the latest command kill stopped: it rejoins as standby.
          for (const auto& k : faults) {
            if (!k.restart && k.target == "command" && k.done && k.instance > 0) f.instance = k.instance;
          }
          if (f.instance == 0 || !command_killed[f.instance - 1]) {
            spdlog::warn("fault injection: no killed incident command to restart at mission second {:.1f}", mission_s);
            continue;
          }
          spdlog::warn("fault injection: restarting {} at mission second {:.1f}", command_name(f.instance), mission_s);
          start_command(f.instance, "-restarted");
          continue;
        }
        if (f.restart) {
          spdlog::warn("fault injection: restarting {} at mission second {:.1f}", f.target, mission_s);
          start_cores("-restarted");  // a new daemon: no filter state survives
          continue;
        }
        if (f.target == "command") {
          f.instance = active_command();
          if (f.instance == 0) {  // no picture heard yet: the one that claims first
            f.instance = 1;
            spdlog::warn("fault injection: no active incident command heard yet: killing instance 1");
          }
          {
            std::lock_guard<std::mutex> lock(picture.mutex);
            const auto it = picture.participant_of_node.find(mission.command_config(f.instance).node_id);
            if (it != picture.participant_of_node.end()) f.killed_participant = it->second;
          }
          f.picture_at_kill = picture.victims_now();
          spdlog::warn("fault injection: killing {} (the active incident command) at mission second {:.1f}",
                       command_name(f.instance), mission_s);
          commands[f.instance - 1]->kill_now();
          command_killed[f.instance - 1] = true;
          continue;
        }
        spdlog::warn("fault injection: killing {} at mission second {:.1f}", f.target, mission_s);
        if (f.target == "core") {
          for (auto& c : cores) c->kill_now();
        } else {
          rescuers.at(f.target)->kill_now();
        }
      }
      {
        std::lock_guard<std::mutex> lock(picture.mutex);
        for (auto& f : faults) {
          if (!f.done || f.link_lost_after_s >= 0.0 || !is_rescuer_kill(f)) continue;
          const auto it = picture.links.find(f.target);
          if (it != picture.links.end() && it->second == incident::LinkState::kLost) {
            f.link_lost_after_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - f.when).count();
            spdlog::info("incident command reports the link to {} lost after {:.1f} s", f.target, f.link_lost_after_s);
          }
        }
        // Handover: the picture comes from another participant than the killed one.
        for (auto& f : faults) {
          if (!f.done || f.restart || f.target != "command" || f.handover_after_s >= 0.0) continue;
          if (picture.owner.empty() || picture.owner == f.killed_participant || picture.owner_since <= f.when) continue;
          f.handover_after_s = std::chrono::duration<double>(picture.owner_since - f.when).count();
          const auto node = picture.node_of_participant.find(picture.owner);
          f.taken_over_by = node == picture.node_of_participant.end() ? picture.owner : node->second;
          spdlog::info("{} took the incident picture over {:.2f} s after the kill", f.taken_over_by, f.handover_after_s);
        }
      }
      // Every buried victim matched by a FOUND victim of the picture (not just as many FOUND
      // as buried: a duplicate whose disposal is still on its way must not end the mission).
      // A building mission goes on while a firefighter still searches (killed ones excepted).
      const bool searching = std::any_of(mission.firefighters.begin(), mission.firefighters.end(), [&](const auto& f) {
        const bool killed = std::any_of(faults.begin(), faults.end(), [&](const Fault& k) {
          return k.done && !k.restart && k.target == f.id;
        });
        return !killed && rescuers.at(f.id)->running();
      });
      if (!searching && mission::every_victim_found(mission.scenario.victims, picture.victims_now())) {
        // Let the pending link-lost detections finish before stopping.
        const bool waiting_link = std::any_of(faults.begin(), faults.end(), [&](const Fault& f) {
          const bool pending = (is_rescuer_kill(f) && f.link_lost_after_s < 0.0) ||
                               (f.target == "command" && !f.restart && f.handover_after_s < 0.0 && instances > 1);
          return f.done && pending && std::chrono::steady_clock::now() - f.when < std::chrono::seconds(30);
        });
        if (!waiting_link) {
          break;
        }
      }
      if (mission_s >= mission.time_limit_s) {
        spdlog::warn("time limit of {:.0f} mission seconds reached", mission.time_limit_s);
        break;
      }
      bool command_failed = false;
      for (unsigned k = 1; k <= instances; ++k) {
        if (command_killed[k - 1] || commands[k - 1]->running()) continue;
        spdlog::error("{} exited unexpectedly (code {}); see {}", commands[k - 1]->name(), commands[k - 1]->exit_code(),
                      log_file(commands[k - 1]->name()));
        command_failed = true;
      }
      if (command_failed) break;
    }
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    const bool command_alive_at_end = std::any_of(commands.begin(), commands.end(), [](auto& c) { return c->running(); });
    bool picture_available = false;
    {
      std::lock_guard<std::mutex> lock(picture.mutex);  // heard within the 3 s lease of the picture writers
      picture_available = !picture.owner.empty() && std::chrono::steady_clock::now() - picture.owner_heard < std::chrono::seconds(3);
    }

    // Rescuers first (they write their summaries), then command (standby instances before the
    // active one, which they would otherwise take over from), then the daemons.
    std::vector<std::string> stopped_in_order;  // devices running until now (killed ones excepted)
    for (auto& [id, r] : rescuers) {
      if (r->running()) stopped_in_order.push_back(id);
      r->stop(std::chrono::seconds(10));
    }
    // Each device stopped in order signs off (sign_off.hpp): give the picture a moment to say so.
    if (command_alive_at_end) {
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
      auto every_one_signed_off = [&] {
        std::lock_guard<std::mutex> lock(picture.mutex);
        return std::all_of(stopped_in_order.begin(), stopped_in_order.end(), [&](const std::string& id) {
          const auto it = picture.links.find(id);
          return it != picture.links.end() && it->second == incident::LinkState::kSignedOff;
        });
      };
      while (!every_one_signed_off() && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    const unsigned last_active = active_command();
    for (unsigned k = 1; k <= instances; ++k) {
      if (k != last_active) commands[k - 1]->stop(std::chrono::seconds(10));
    }
    if (last_active > 0) commands[last_active - 1]->stop(std::chrono::seconds(10));
    for (auto& c : cores) c->stop(std::chrono::seconds(10));
    if (dashboard_process) dashboard_process->stop(std::chrono::seconds(5));
    // The recorder last: it writes the summary of the file when it stops.
    if (recorder) {
      const int code = recorder->stop(std::chrono::seconds(20));
      if (code != 0) {
        spdlog::error("the recorder ended with exit code {}: see {}; the recording may need sarloc-record --recover",
                      code, log_file("record"));
      }
    }

    // What each rescuer's device knew (its summary): found signals and their own errors.
    std::map<std::string, mission::DeviceSummary> devices;
    for (const auto& r : mission.scenario.rescuers) {
      std::ifstream in(fs::path(run_dir) / (r.id + ".json"));
      if (!in) continue;
      try {
        devices[r.id] = app::device_summary_from_json(nlohmann::json::parse(in));
      } catch (const std::exception& e) {
        spdlog::warn("cannot read {}'s summary: {}", r.id, e.what());
      }
    }
    auto summary = mission::summarise_mission(mission.name, mission.scenario, picture.victims_now(), epoch, devices);
    for (const auto& f : mission.firefighters) {
      std::ifstream in(fs::path(run_dir) / (f.id + ".json"));
      try {
        if (!in) throw std::runtime_error("no summary file (killed?)");
        summary.firefighters.push_back(app::firefighter_summary_from_json(nlohmann::json::parse(in)));
      } catch (const std::exception& e) {
        spdlog::warn("cannot read {}'s summary: {}", f.id, e.what());
        summary.firefighters_without_summary.push_back(f.id);
      }
    }
    {
      std::lock_guard<std::mutex> lock(picture.mutex);
      for (const auto& [id, a] : picture.alarms) {
        mission::MissionSummary::PictureAlarm p;
        p.alarm_id = id;
        p.kind = responder::to_string(a.alarm.kind);
        p.responder_id = a.alarm.responder_id;
        p.raised_s = 1e-9 * static_cast<double>(a.alarm.raised_at - epoch);
        if (!a.alarm.active) p.cleared_s = 1e-9 * static_cast<double>(a.alarm.cleared_at - epoch);
        summary.picture_alarms.push_back(p);
      }
      for (const auto& [id, link] : picture.links) summary.links_at_end[id] = incident::to_string(link);
    }
    summary.mission_s = mission_s;
    summary.wall_s = wall_s;
    summary.command_alive_at_end = command_alive_at_end;
    summary.picture_available = picture_available;
    for (const auto& f : faults) {
      mission::FaultOutcome outcome;
      outcome.action = f.restart ? "restart" : "kill";
      outcome.target = f.target;
      outcome.at_s = f.at_s;
      outcome.done = f.done;
      if (f.link_lost_after_s >= 0.0) outcome.link_lost_after_s = f.link_lost_after_s;
      if (f.handover_after_s >= 0.0) outcome.handover_after_s = f.handover_after_s;
      outcome.taken_over_by = f.taken_over_by;
      outcome.picture_at_kill = mission::picture_outcomes(mission.scenario, f.picture_at_kill, epoch);
      summary.faults.push_back(outcome);
    }
    print_summary(summary, run_dir);
    if (!recording_path.empty()) std::printf("recording: %s\n", recording_path.c_str());
    if (!json_path.empty()) {
      nlohmann::json j = app::to_json(summary);
      if (!recording_path.empty()) j["recording"] = recording_path;
      app::write_json_file(json_path, j);
    }
    if (interrupted) return app::ExitCode::kInterrupted;
    // Every firefighter's device reported, and each converged on the map.
    const bool firefighters_ok = summary.firefighters_without_summary.empty() &&
                                 std::all_of(summary.firefighters.begin(), summary.firefighters.end(),
                                             [](const auto& f) { return f.converged_at_s.has_value(); });
    return summary.all_found && firefighters_ok ? app::ExitCode::kOk : app::ExitCode::kFailure;
  });
}
