// sarloc-mission: sarloc's main job. Starts the core daemon(s), one sarloc-rescuer process per
// rescuer and command.instances sarloc-command processes (one active, the others standing by)
// as separate processes over DDS, watches the incident picture like a dashboard would, stops
// everything when every victim is found or the time limit passes, and prints the summary.
// Exit 0 only when every victim was found.
//
// Its parts: MissionOptions (the command line), ProcessTable (starts, kills and stops the
// processes), FaultPlan (--kill, --restart and what the picture showed after each),
// PictureWatcher (the picture over DDS), mission::assemble_mission_summary (core/mission) and
// print_summary. This file only orchestrates them.
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "fault_plan.hpp"
#include "mission_options.hpp"
#include "picture_watcher.hpp"
#include "process_table.hpp"
#include "sarloc/app/command_line.hpp"
#include "sarloc/app/json_io.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/mission_config.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/common/time_units.hpp"
#include "sarloc/core/mission/survival_outlook.hpp"
#include "sarloc/core/mission/victim_matching.hpp"
#include "sarloc/dds/recorder.hpp"
#include "summary_table.hpp"

namespace {

using namespace sarloc;
namespace fs = std::filesystem;
using SteadyClock = std::chrono::steady_clock;

// The instance publishing the picture now (0: none heard yet).
unsigned active_instance(const app::PictureWatcher& picture, const app::MissionConfig& mission) {
  const auto node = picture.publisher().node_id;
  for (unsigned k = 1; k <= mission.command_instances() && !node.empty(); ++k) {
    if (mission.command_config(k).node_id == node) return k;
  }
  return 0;
}

void inject(app::Fault& f, app::ProcessTable& processes, const app::PictureWatcher& picture,
            const app::MissionConfig& mission, double mission_s) {
  if (f.restart && f.target == "command") {  // the instance the latest command kill stopped: it rejoins as standby
    if (f.instance == 0 || !processes.command_killed(f.instance)) {
      spdlog::warn("fault injection: no killed incident command to restart at mission second {:.1f}", mission_s);
      return;
    }
    spdlog::warn("fault injection: restarting {} at mission second {:.1f}", processes.command_name(f.instance), mission_s);
    processes.start_command(f.instance, "-restarted");
  } else if (f.restart) {
    spdlog::warn("fault injection: restarting {} at mission second {:.1f}", f.target, mission_s);
    processes.start_cores("-restarted");  // a new daemon: no filter state survives
  } else if (f.target == "command") {
    f.instance = active_instance(picture, mission);
    if (f.instance == 0) {  // no picture heard yet: the one that claims first
      f.instance = 1;
      spdlog::warn("fault injection: no active incident command heard yet: killing instance 1");
    }
    f.killed_participant = picture.participant_of(mission.command_config(f.instance).node_id);
    f.picture_at_kill = picture.victims();
    spdlog::warn("fault injection: killing {} (the active incident command) at mission second {:.1f}",
                 processes.command_name(f.instance), mission_s);
    processes.kill_command(f.instance);
  } else {
    spdlog::warn("fault injection: killing {} at mission second {:.1f}", f.target, mission_s);
    if (f.target == "core") {
      processes.kill_cores();
    } else {
      processes.kill_device(f.target);
    }
  }
}

// Runs until every buried victim is matched by a FOUND victim of the picture (not just as many
// FOUND as buried: a duplicate whose disposal is still on its way must not end the mission),
// no firefighter still searches (killed ones excepted) and no fault waits for what it should
// show; or the time limit; or a command instance fails. Returns false when interrupted.
bool run_until_done(const app::MissionConfig& mission, const sarloc::dds::MissionClock& clock, TimestampNs epoch,
                    app::ProcessTable& processes, app::FaultPlan& faults, const app::PictureWatcher& picture,
                    double& mission_s) {
  while (true) {
    if (app::wait_for_shutdown(std::chrono::milliseconds(100))) return false;
    mission_s = ns_to_seconds(clock.now() - epoch);
    for (app::Fault* f : faults.due(mission_s, SteadyClock::now())) inject(*f, processes, picture, mission, mission_s);
    const auto now = SteadyClock::now();
    faults.observe_links(picture.links(), now);
    const auto publisher = picture.publisher();
    faults.observe_publisher(publisher.participant, publisher.since, publisher.node_id);
    const bool searching = std::any_of(mission.firefighters.begin(), mission.firefighters.end(), [&](const auto& f) {
      return !faults.killed(f.id) && processes.device_running(f.id);
    });
    if (!searching && mission::every_victim_found(mission.scenario.victims, picture.victims()) &&
        !faults.awaiting_observation(SteadyClock::now(), mission.command_instances())) {
      return true;
    }
    if (mission_s >= mission.time_limit_s) {
      spdlog::warn("time limit of {:.0f} mission seconds reached", mission.time_limit_s);
      return true;
    }
    if (processes.a_command_failed()) return true;
  }
}

// What each device knew (its summary file in the run folder).
void read_device_summaries(const app::MissionConfig& mission, const fs::path& run_dir, mission::MissionEnd& end) {
  for (const auto& r : mission.scenario.rescuers) {
    std::ifstream in(run_dir / (r.id + ".json"));
    if (!in) continue;
    try {
      end.devices[r.id] = app::device_summary_from_json(nlohmann::json::parse(in));
    } catch (const std::exception& e) {
      spdlog::warn("cannot read {}'s summary: {}", r.id, e.what());
    }
  }
  for (const auto& f : mission.firefighters) {
    std::ifstream in(run_dir / (f.id + ".json"));
    try {
      if (!in) throw std::runtime_error("no summary file (killed?)");
      end.firefighters.push_back(app::firefighter_summary_from_json(nlohmann::json::parse(in)));
    } catch (const std::exception& e) {
      spdlog::warn("cannot read {}'s summary: {}", f.id, e.what());
      end.firefighters_without_summary.push_back(f.id);
    }
  }
}

// Devices first (each signs off: the picture is given a moment to say so), then incident
// command with the active instance last, the daemons and the recorder.
void stop_in_order(app::ProcessTable& processes, const app::PictureWatcher& picture, const app::MissionConfig& mission,
                   mission::MissionEnd& end) {
  end.command_alive_at_end = processes.any_command_running();
  end.picture_available = picture.available(SteadyClock::now());
  const auto stopped = processes.stop_devices();
  const auto deadline = SteadyClock::now() + std::chrono::seconds(5);
  while (end.command_alive_at_end && !picture.signed_off(stopped) && SteadyClock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  processes.stop_the_rest(active_instance(picture, mission));
}

}  // namespace

int main(int argc, char** argv) {
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-mission: a whole simulated mission (avalanche, building or both) over DDS on this machine"};
  app::MissionOptions options;
  app::add_mission_options(cli, options);
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-mission", [&]() -> app::ExitCode {
    app::setup_logging(options.log_level, "mission");
    const auto mission = app::load_mission_config(options.config_path);
    if (options.identities) {
      for (const auto& identity : mission.security_identities()) std::cout << identity << '\n';
      return app::ExitCode::kOk;
    }
    auto faults = app::FaultPlan::parse(options.kills, options.restarts);
    for (const auto& f : faults.faults()) {
      if (f.is_device_kill()) (void)mission.team_of(f.target);  // known id?
    }
    app::ProcessTableConfig table;
    table.hosts = options.hosts();
    table.launcher = options.launcher;
    table.bin_dir = fs::canonical("/proc/self/exe").parent_path();
    for (const auto& name : app::ProcessTable::programs(options.dashboard)) {  // scripts/demo builds only these
      if (!fs::exists(table.bin_dir / name)) {
        throw std::runtime_error(name + " is not in " + table.bin_dir.string() + ": build it first (scripts/build --target " + name + ")");
      }
    }
    table.run_dir = options.run_dir.empty() ? fs::temp_directory_path() / ("sarloc-mission-" + std::to_string(getpid()))
                                            : fs::path(options.run_dir);
    fs::create_directories(table.run_dir);
    table.mission_file = fs::absolute(options.config_path).string();
    table.log_level = options.log_level;
    spdlog::info("mission '{}': {} victims, {} rescuers, {} firefighters, speedup {}x; logs in {}", mission.name,
                 mission.scenario.victims.size(), mission.scenario.rescuers.size(), mission.firefighters.size(),
                 mission.speedup, table.run_dir.string());
    // The mission's own participant watches the picture like incident command's dashboard.
    const auto dds_config = app::participant_config(mission, options.domain, "sarloc-mission", app::kMissionIdentity);
    table.domain_id = dds_config.domain_id;
    const app::PictureWatcher picture(std::make_shared<sarloc::dds::Participant>(dds_config));
    // Mission time starts a little in the future so every process is up and discovered.
    table.epoch_ns = sarloc::dds::MissionClock::wall_now_ns() + seconds_to_ns(options.startup_s);
    const sarloc::dds::MissionClock clock(table.epoch_ns, mission.speedup);
    app::ProcessTable processes(mission, table);

    std::string recording;  // the recorder first, so that it hears every process from its first sample
    if (!options.no_record) {
      const auto folder = options.record_dir.empty() ? mission.record_directory : options.record_dir;
      recording = fs::absolute(sarloc::dds::timestamped_recording_path(folder, mission.name)).string();
      processes.start_recorder(recording);
      spdlog::info("recording the mission to {}", recording);
    }
    if (options.dashboard) processes.start_dashboard(options.dashboard_port);
    processes.start_cores();
    for (unsigned k = 1; k <= mission.command_instances(); ++k) processes.start_command(k);  // 1 claims first
    processes.start_devices();

    const auto wall_start = SteadyClock::now();
    mission::MissionEnd end;
    const bool completed = run_until_done(mission, clock, table.epoch_ns, processes, faults, picture, end.mission_s);
    end.wall_s = std::chrono::duration<double>(SteadyClock::now() - wall_start).count();
    stop_in_order(processes, picture, mission, end);
    read_device_summaries(mission, table.run_dir, end);
    end.picture = picture.victims();
    end.alarms = picture.alarms();
    end.links = picture.links();
    end.faults = faults.outcomes(mission.scenario, table.epoch_ns);
    auto summary = mission::assemble_mission_summary(mission.name, mission.scenario, table.epoch_ns, std::move(end));
    if (!summary.victims.empty()) mission::add_survival_outlook(summary, mission.command.incident.triage);
    app::print_summary(summary, table.run_dir.string());
    if (!recording.empty()) std::printf("recording: %s\n", recording.c_str());
    if (!options.json_path.empty()) {
      nlohmann::json j = app::to_json(summary);
      if (!recording.empty()) j["recording"] = recording;
      app::write_json_file(options.json_path, j);
    }
    if (!completed) return app::ExitCode::kInterrupted;
    // Every firefighter's device reported, and each converged on the map.
    const bool firefighters_ok = summary.firefighters_without_summary.empty() &&
                                 std::all_of(summary.firefighters.begin(), summary.firefighters.end(),
                                             [](const auto& f) { return f.converged_at_s.has_value(); });
    return summary.all_found && firefighters_ok ? app::ExitCode::kOk : app::ExitCode::kFailure;
  });
}
