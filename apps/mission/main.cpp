// sarloc-mission: sarloc's main job. Starts the core daemon(s), one sarloc-rescuer process per
// rescuer and sarloc-command as separate processes over DDS, watches the incident picture like
// a dashboard would, stops everything when every victim is found or the time limit passes, and
// prints the summary. Exit 0 only when every victim was found.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "sarloc/app/child_process.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/mission_config.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/incident/assignment.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/reader.hpp"

namespace {

using namespace sarloc;
namespace fs = std::filesystem;

struct Fault {
  bool restart = false;  ///< --restart (start again what an earlier --kill stopped) instead of --kill
  std::string target;  ///< "core", "command" or a rescuer id
  double at_s = 0.0;   ///< mission seconds
  bool done = false;
  std::chrono::steady_clock::time_point when{};
  double link_lost_after_s = -1.0;  ///< rescuer faults: wall seconds until command reported it lost
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
  if (restart && f.target != "core") throw ConfigError(option + " = '" + text + "': only core can be restarted");
  return f;
}

// Fused victims matched one-to-one to the buried ones (minimum total distance, at most
// kMatchRadius apart): index of the fused victim per true victim, or -1.
constexpr double kMatchRadius = 5.0;

// A fault that kills one rescuer's device (not a daemon, not incident command).
bool is_rescuer_kill(const Fault& f) { return f.target != "core" && f.target != "command"; }

std::vector<int> match_to_truth(const std::vector<mission::VictimSpec>& truth,
                                const std::vector<incident::FusedVictim>& fused) {
  if (fused.empty()) return std::vector<int>(truth.size(), -1);
  Eigen::MatrixXd cost(static_cast<Eigen::Index>(truth.size()), static_cast<Eigen::Index>(fused.size()));
  for (std::size_t i = 0; i < truth.size(); ++i) {
    for (std::size_t j = 0; j < fused.size(); ++j) {
      const double d = (fused[j].position.position - truth[i].position).norm();
      cost(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = d <= kMatchRadius ? d : incident::kInfeasible;
    }
  }
  return incident::solve_assignment(cost);
}

// The incident picture as a late-joining dashboard sees it.
struct Picture {
  std::mutex mutex;
  std::map<std::uint32_t, incident::FusedVictim> victims;
  std::map<std::string, incident::LinkState> links;
  std::vector<std::pair<eprosima::fastrtps::rtps::InstanceHandle_t, std::uint32_t>> instances;

  /// The fused victims now (copied, so matching runs without the lock).
  std::vector<incident::FusedVictim> victims_now() {
    std::lock_guard<std::mutex> lock(mutex);
    std::vector<incident::FusedVictim> out;
    for (const auto& [id, v] : victims) out.push_back(v);
    return out;
  }
};

}  // namespace

int main(int argc, char** argv) {
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-mission: a whole simulated avalanche mission over DDS on this machine"};
  std::string config_path = SARLOC_SOURCE_DIR "/config/missions/default.yaml";
  std::string json_path;
  std::string run_dir;
  std::string log_level = "info";
  std::vector<std::string> kills;
  std::vector<std::string> restarts;
  double startup_s = 3.0;
  int domain = -1;
  cli.add_option("mission", config_path, "mission YAML")->capture_default_str();
  cli.add_option("--json", json_path, "write the summary as JSON here");
  cli.add_option("--run-dir", run_dir, "folder for the processes' logs and summaries (default: a new one in /tmp)");
  cli.add_option("--restart", restarts, "start the core daemon(s) again at mission SECONDS after a --kill, e.g. core@25");
  cli.add_option("--kill", kills, "fault injection: SIGKILL TARGET (core, command or a rescuer id) at mission SECONDS, e.g. core@40");
  cli.add_option("--startup", startup_s, "wall seconds given to the processes to start and discover each other");
  cli.add_option("--domain", domain, "DDS domain id for every process, overriding dds.domain_id of the mission");
  cli.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical, off");
  cli.set_version_flag("--version", SARLOC_VERSION);
  CLI11_PARSE(cli, argc, argv);

  return app::run_main("sarloc-mission", [&]() -> app::ExitCode {
    app::setup_logging(log_level, "mission");
    const auto mission = app::load_mission_config(config_path);
    std::vector<Fault> faults;
    for (const auto& k : kills) {
      auto f = parse_fault(k, false);
      if (f.target != "core" && f.target != "command") mission.scenario.rescuer_index(f.target);  // known id?
      faults.push_back(f);
    }
    for (const auto& r : restarts) faults.push_back(parse_fault(r, true));
    const fs::path bin_dir = fs::canonical("/proc/self/exe").parent_path();
    if (run_dir.empty()) run_dir = (fs::temp_directory_path() / ("sarloc-mission-" + std::to_string(getpid()))).string();
    fs::create_directories(run_dir);
    const std::string config_abs = fs::absolute(config_path).string();
    spdlog::info("mission '{}': {} victims, {} rescuers, speedup {}x; logs in {}", mission.name,
                 mission.scenario.victims.size(), mission.scenario.rescuers.size(), mission.speedup, run_dir);

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
    sarloc::dds::Reader<::sarloc::TeamStatus> team_reader(participant, [&](const ::sarloc::TeamStatus& t, const auto&) {
      try {
        const auto team = sarloc::dds::to_core(t);
        std::lock_guard<std::mutex> lock(picture.mutex);
        for (const auto& m : team.members) picture.links[m.responder_id] = m.link;
      } catch (const InputError& e) {
        spdlog::warn("ignoring a team status: {}", e.what());
      }
    });
    sarloc::dds::Reader<::sarloc::IncidentSummary> summary_reader(participant, [](const auto&, const auto&) {});

    // Mission time starts a little in the future so every process is up and discovered.
    const TimestampNs epoch = sarloc::dds::MissionClock::wall_now_ns() + static_cast<TimestampNs>(startup_s * 1e9);
    const sarloc::dds::MissionClock clock(epoch, mission.speedup);
    const std::string epoch_arg = std::to_string(epoch);
    auto log_file = [&](const std::string& name) { return (fs::path(run_dir) / (name + ".log")).string(); };

    std::vector<std::unique_ptr<app::ChildProcess>> cores;
    std::vector<std::string> sectors = mission.sectors.empty() ? std::vector<std::string>{""} : mission.sectors;
    auto start_cores = [&](const std::string& suffix) {
      cores.clear();
      for (const auto& sector : sectors) {
        std::vector<std::string> args{(bin_dir / "sarloc-core").string(), "-c", config_abs, "--domain", domain_arg,
                                      "--log-level", log_level};
        if (!sector.empty()) args.insert(args.end(), {"--sector", sector});
        const std::string name = (sector.empty() ? "core" : "core-" + sector) + suffix;
        cores.push_back(std::make_unique<app::ChildProcess>(name, args, log_file(name)));
      }
    };
    start_cores("");
    auto command = std::make_unique<app::ChildProcess>(
        "command",
        std::vector<std::string>{(bin_dir / "sarloc-command").string(), "-c", config_abs, "--epoch-ns", epoch_arg,
                                 "--summary", (fs::path(run_dir) / "command.json").string(), "--domain", domain_arg, "--log-level", log_level},
        log_file("command"));
    std::map<std::string, std::unique_ptr<app::ChildProcess>> rescuers;
    for (const auto& r : mission.scenario.rescuers) {
      rescuers[r.id] = std::make_unique<app::ChildProcess>(
          "rescuer-" + r.id,
          std::vector<std::string>{(bin_dir / "sarloc-rescuer").string(), "-c", config_abs, "--id", r.id, "--epoch-ns",
                                   epoch_arg, "--summary", (fs::path(run_dir) / (r.id + ".json")).string(),
                                   "--domain", domain_arg, "--log-level", log_level},
          log_file("rescuer-" + r.id));
    }

    const auto wall_start = std::chrono::steady_clock::now();
    const std::size_t true_count = mission.scenario.victims.size();
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
        if (f.restart) {
          spdlog::warn("fault injection: restarting {} at mission second {:.1f}", f.target, mission_s);
          start_cores("-restarted");  // a new daemon: no filter state survives
          continue;
        }
        spdlog::warn("fault injection: killing {} at mission second {:.1f}", f.target, mission_s);
        if (f.target == "core") {
          for (auto& c : cores) c->kill_now();
        } else if (f.target == "command") {
          command->kill_now();
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
      }
      // Every buried victim matched by a FOUND victim of the picture (not just as many FOUND
      // as buried: a duplicate whose disposal is still on its way must not end the mission).
      const auto now = picture.victims_now();
      const auto matched = match_to_truth(mission.scenario.victims, now);
      const bool every_victim_found = std::all_of(matched.begin(), matched.end(), [&](int j) {
        return j >= 0 && incident::is_found(now[static_cast<std::size_t>(j)].state);
      });
      if (every_victim_found) {
        // Let the pending link-lost detections finish before stopping.
        const bool waiting_link = std::any_of(faults.begin(), faults.end(), [&](const Fault& f) {
          return f.done && f.link_lost_after_s < 0.0 && is_rescuer_kill(f) &&
                 std::chrono::steady_clock::now() - f.when < std::chrono::seconds(30);
        });
        if (!waiting_link) {
          break;
        }
      }
      if (mission_s >= mission.time_limit_s) {
        spdlog::warn("time limit of {:.0f} mission seconds reached", mission.time_limit_s);
        break;
      }
      if (!command->running()) {
        const bool killed = std::any_of(faults.begin(), faults.end(), [](const Fault& f) { return f.target == "command"; });
        if (!killed) {
          spdlog::error("sarloc-command exited unexpectedly (code {}); see {}", command->exit_code(), log_file("command"));
          break;
        }
      }
    }
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    // Rescuers first (they write their summaries), then command, then the daemons.
    for (auto& [id, r] : rescuers) r->stop(std::chrono::seconds(10));
    command->stop(std::chrono::seconds(10));
    for (auto& c : cores) c->stop(std::chrono::seconds(10));

    // Match fused victims to the truth (minimum total distance, at most match_radius apart).
    const auto fused = picture.victims_now();
    const auto match = match_to_truth(mission.scenario.victims, fused);

    // What each rescuer's device knew (its summary): found signals and their own errors.
    std::map<std::string, nlohmann::json> device;
    for (const auto& r : mission.scenario.rescuers) {
      std::ifstream in(fs::path(run_dir) / (r.id + ".json"));
      if (!in) continue;
      try {
        device[r.id] = nlohmann::json::parse(in);
      } catch (const std::exception& e) {
        spdlog::warn("cannot read {}'s summary: {}", r.id, e.what());
      }
    }
    // The diggers' view of victim i: the smallest error of a device that found it, relative to
    // that device (no GNSS involved).
    auto relative_error_of = [&](std::size_t victim) -> std::optional<double> {
      std::optional<double> best;
      for (const auto& [id, s] : device) {
        for (const auto& signal : s.value("signals", nlohmann::json::array())) {
          if (signal.value("victim_index", -1) != static_cast<int>(victim) || signal.value("status", "") != "FOUND") continue;
          if (!signal.contains("relative_error_m")) continue;
          const double e = signal["relative_error_m"].get<double>();
          if (!best || e < *best) best = e;
        }
      }
      return best;
    };

    nlohmann::json out;
    out["mission"] = mission.name;
    out["true_victim_count"] = true_count;
    out["fused_victim_count"] = fused.size();
    out["victims"] = nlohmann::json::array();
    bool all_found = true;
    std::printf("\n%-10s %-26s %-26s %8s %10s %12s %6s\n", "victim", "true position (E N U) m", "fused estimate m",
                "error m", "finder m", "located s", "found");
    for (std::size_t i = 0; i < true_count; ++i) {
      const auto& truth = mission.scenario.victims[i];
      nlohmann::json v{{"name", truth.name},
                       {"true_position", {truth.position.x(), truth.position.y(), truth.position.z()}}};
      const int j = match[i];
      bool found = false;
      char est[64] = "-";
      char err[32] = "-";
      char located[32] = "-";
      if (j >= 0) {
        const auto& f = fused[static_cast<std::size_t>(j)];
        const double error = (f.position.position - truth.position).norm();
        found = incident::is_found(f.state);
        v["victim_id"] = f.victim_id;
        v["estimate"] = {f.position.position.x(), f.position.position.y(), f.position.position.z()};
        v["error_m"] = error;
        v["sources"] = f.sources.size();
        std::snprintf(est, sizeof(est), "(%.1f, %.1f, %.1f)", f.position.position.x(), f.position.position.y(),
                      f.position.position.z());
        std::snprintf(err, sizeof(err), "%.2f", error);
        if (f.located_at > 0) {
          const double t = static_cast<double>(f.located_at - epoch) / 1e9;
          v["time_to_locate_s"] = t;
          std::snprintf(located, sizeof(located), "%.0f", t);
        } else {
          v["time_to_locate_s"] = nullptr;
        }
      } else {
        v["error_m"] = nullptr;
        v["time_to_locate_s"] = nullptr;
      }
      v["found"] = found;
      if (const auto relative = relative_error_of(i)) {
        v["relative_error_m"] = *relative;
      } else {
        v["relative_error_m"] = nullptr;
      }
      all_found = all_found && found;
      out["victims"].push_back(v);
      char truth_text[64];
      std::snprintf(truth_text, sizeof(truth_text), "(%.1f, %.1f, %.1f)", truth.position.x(), truth.position.y(),
                    truth.position.z());
      char finder[32] = "-";
      if (!v["relative_error_m"].is_null()) std::snprintf(finder, sizeof(finder), "%.2f", v["relative_error_m"].get<double>());
      std::printf("%-10s %-26s %-26s %8s %10s %12s %6s\n", truth.name.c_str(), truth_text, est, err, finder, located,
                  found ? "yes" : "NO");
    }
    out["all_found"] = all_found;
    // Every victim of the picture, and whether it is one of the buried ones: a confirmed
    // (LOCATED/FOUND) victim that matches none is a duplicate incident command would dig for.
    out["fused_victims"] = nlohmann::json::array();
    std::size_t confirmed = 0;
    for (std::size_t j = 0; j < fused.size(); ++j) {
      const auto& f = fused[j];
      const bool matched = std::find(match.begin(), match.end(), static_cast<int>(j)) != match.end();
      const bool is_confirmed = f.state != incident::VictimState::kUnconfirmed;
      confirmed += is_confirmed ? 1 : 0;
      out["fused_victims"].push_back({{"victim_id", f.victim_id},
                                      {"position", {f.position.position.x(), f.position.position.y(), f.position.position.z()}},
                                      {"confirmed", is_confirmed},
                                      {"found", incident::is_found(f.state)},
                                      {"sources", f.sources.size()},
                                      {"matches_a_buried_victim", matched}});
    }
    out["confirmed_fused_victim_count"] = confirmed;
    out["mission_s"] = mission_s;
    out["wall_s"] = wall_s;
    out["rescuers"] = nlohmann::json::array();
    std::printf("\n%-10s %18s %10s %22s\n", "rescuer", "distance walked m", "fallbacks", "latency p50/p99 ms");
    for (const auto& r : mission.scenario.rescuers) {
      nlohmann::json entry{{"id", r.id}};
      if (const auto it = device.find(r.id); it != device.end()) {
        const auto& s = it->second;
        entry["distance_walked_m"] = s.value("distance_walked_m", 0.0);
        entry["fallbacks"] = s.value("fallbacks", 0);
        entry["latency_ms"] = s.value("latency_ms", nlohmann::json::object());
        entry["gnss_error_m"] = s.value("gnss_error_m", -1.0);
        entry["guided_by"] = s.value("guided_by", nlohmann::json::object());
        entry["daemon_after_fallback"] = s.value("daemon_after_fallback", 0);
        std::printf("%-10s %18.1f %10d %10.1f / %-10.1f\n", r.id.c_str(), s.value("distance_walked_m", 0.0),
                    s.value("fallbacks", 0), entry["latency_ms"].value("p50", -1.0),
                    entry["latency_ms"].value("p99", -1.0));
      } else {
        std::printf("%-10s %18s\n", r.id.c_str(), "(no summary: killed?)");
      }
      out["rescuers"].push_back(entry);
    }
    out["faults"] = nlohmann::json::array();
    for (const auto& f : faults) {
      nlohmann::json fj{{"action", f.restart ? "restart" : "kill"}, {"target", f.target}, {"at_s", f.at_s}, {"done", f.done}};
      if (f.link_lost_after_s >= 0.0) fj["link_lost_after_s"] = f.link_lost_after_s;
      out["faults"].push_back(fj);
    }
    std::printf("\n%zu of %zu victims found, %zu in the incident picture; %.0f mission s in %.0f wall s. Logs: %s\n",
                static_cast<std::size_t>(std::count_if(out["victims"].begin(), out["victims"].end(),
                                                       [](const auto& v) { return v["found"].template get<bool>(); })),
                true_count, fused.size(), mission_s, wall_s, run_dir.c_str());
    if (!json_path.empty()) std::ofstream(json_path) << out.dump(2) << "\n";
    if (interrupted) return app::ExitCode::kInterrupted;
    return all_found ? app::ExitCode::kOk : app::ExitCode::kFailure;
  });
}
