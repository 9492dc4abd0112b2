// sarloc-replay: re-publishes a recording over DDS with its recorded timing (docs/operations/
// recording.md). With --run-nodes it also starts a fresh sarloc-core and sarloc-command on the
// recorded timeline (configured by -c: change it to try other parameters) and, with --record,
// records what they compute; sarloc-report NEW.mcap --compare OLD.mcap shows the difference.
//
// Exit codes: 0 replayed; 1 replayed, but some samples could not be written or a node failed;
// 2 bad command line; 3 bad mission file or options; 4 not a recording, DDS or a child failed
// to start.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>

#include "sarloc/core/common/time_units.hpp"
#include "sarloc/app/child_process.hpp"
#include "sarloc/app/command_line.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/progress_bar.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/replayer.hpp"

namespace fs = std::filesystem;

namespace {

// The original's sarloc.recording metadata values (mission file, floor plan) for the replay's
// own recording, so that its report has the same truth and building.
std::map<std::string, std::string> recording_metadata(const std::string& path) {
  std::map<std::string, std::string> values;
  sarloc::recording::McapVisitor visitor;
  visitor.on_metadata = [&](const sarloc::recording::Metadata& m) {
    if (m.name == "sarloc.recording") values = m.values;
  };
  sarloc::recording::read_mcap(path, visitor);
  return values;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sarloc;
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-replay: re-publish a recording over DDS with its recorded timing"};
  sarloc::dds::ReplayConfig config;
  std::string config_path, log_level = "info", record_path, run_dir;
  int domain = -1;
  bool run_nodes = false;
  double startup_s = 3.0, tail_s = 3.0;
  cli.add_option("recording", config.recording, "the .mcap file")->required();
  cli.add_option("-c,--config", config_path, "mission YAML: DDS settings, and the fresh nodes' configuration with --run-nodes")
      ->required();
  cli.add_option("--domain", domain, "DDS domain id, overriding dds.domain_id of the config");
  cli.add_option("--rate", config.rate, "replay speed: 2 is twice as fast as recorded")->capture_default_str();
  cli.add_option("--start", config.start_s, "first mission second to replay")->capture_default_str();
  cli.add_option("--end", config.end_s, "last mission second to replay (default: the end)");
  cli.add_option("--topics", config.topics, "topics to replay, e.g. sarloc/odometry (default: every one)")->delimiter(',');
  cli.add_flag("--inputs-only", config.inputs_only,
               "only what the devices measured or decided: field measurements, odometry, their own positions, "
               "estimates and alarms");
  cli.add_flag("--run-nodes", run_nodes, "start a fresh sarloc-core and sarloc-command (configured by -c) on the recorded timeline");
  cli.add_option("--record", record_path, "record the replay (and what the fresh nodes publish) into this .mcap file");
  cli.add_option("--run-dir", run_dir, "folder for the child processes' logs (default: a new one in /tmp)");
  cli.add_option("--startup", startup_s, "wall seconds given to discovery before the first message")->capture_default_str();
  cli.add_option("--tail", tail_s, "wall seconds the nodes keep running after the last message")->capture_default_str();
  app::add_log_level_option(cli, log_level);
  cli.set_version_flag("--version", SARLOC_VERSION);
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-replay", [&] {
    app::setup_logging(log_level, "replay");
    if (!std::isfinite(startup_s) || startup_s < 0.0 || startup_s > 60.0) throw ConfigError("--startup must be in [0, 60] s");
    if (!std::isfinite(tail_s) || tail_s < 0.0 || tail_s > 600.0) throw ConfigError("--tail must be in [0, 600] s");
    const auto mission = app::load_mission_config(config_path);
    if (!mission.security_dir.empty()) {
      // Its one participant writes what every node wrote: no identity's permissions allow that.
      throw ConfigError(config_path + ": dds.security_dir = '" + mission.security_dir +
                        "': a replay publishes every node's samples from one participant, which no DDS Security "
                        "identity may; replay with a loopback mission file without dds.security_dir");
    }
    const auto participant_config = app::participant_config(mission, domain, "sarloc-replay", "sarloc-replay");
    auto participant = std::make_shared<sarloc::dds::Participant>(participant_config);
    sarloc::dds::Replayer replayer(participant, config);
    const auto timeline = replayer.timeline();
    const std::int64_t wall_start = sarloc::dds::MissionClock::wall_now_ns() + seconds_to_ns(startup_s);
    const std::int64_t epoch_wall = replayer.epoch_wall_ns(wall_start);

    // The fresh nodes and the recorder, all on the recorded timeline.
    const fs::path bin_dir = fs::canonical("/proc/self/exe").parent_path();
    if (run_dir.empty()) run_dir = (fs::temp_directory_path() / ("sarloc-replay-" + std::to_string(::getpid()))).string();
    fs::create_directories(run_dir);
    const std::string config_abs = fs::absolute(config_path).string();
    const std::string domain_arg = std::to_string(participant_config.domain_id);
    const std::vector<std::string> clock_args{"--epoch-ns", std::to_string(timeline.epoch_ns), "--epoch-wall-ns",
                                              std::to_string(epoch_wall), "--speedup",
                                              std::to_string(timeline.speedup * config.rate)};
    std::vector<std::unique_ptr<app::ChildProcess>> children;
    auto start = [&](const std::string& name, std::vector<std::string> args) {
      children.push_back(std::make_unique<app::ChildProcess>(name, args, (fs::path(run_dir) / (name + ".log")).string()));
    };
    if (!record_path.empty()) {
      std::vector<std::string> args{(bin_dir / "sarloc-record").string(), "-c", config_abs, "--domain", domain_arg,
                                    "-o", record_path, "--log-level", log_level,
                                    "--meta", "epoch_ns=" + std::to_string(timeline.epoch_ns),
                                    "--meta", "speedup=" + std::to_string(timeline.speedup),
                                    "--meta", "replay_of=" + fs::absolute(config.recording).string()};
      const auto original = recording_metadata(config.recording);
      for (const char* key : {"mission_yaml", "building_plan_yaml"}) {
        if (!original.count(key)) continue;
        const fs::path copy = fs::path(run_dir) / (std::string(key) + ".txt");
        std::ofstream(copy) << original.at(key);
        args.insert(args.end(), {"--meta-file", std::string(key) + "=" + copy.string()});
      }
      start("record", args);
    }
    if (run_nodes) {
      // The daemon keeps no clock of its own (it goes by the samples' stamps); incident command does.
      start("core", {(bin_dir / "sarloc-core").string(), "-c", config_abs, "--domain", domain_arg, "--log-level", log_level});
      std::vector<std::string> command{(bin_dir / "sarloc-command").string(), "-c", config_abs, "--instance", "1",
                                       "--domain", domain_arg, "--log-level", log_level};
      command.insert(command.end(), clock_args.begin(), clock_args.end());
      start("command", command);
    }
    spdlog::info("replaying '{}' from mission second {} at rate {}{}{}; logs in {}", config.recording, config.start_s, config.rate,
                 config.inputs_only ? ", inputs only" : "", run_nodes ? ", into a fresh core daemon and incident command" : "",
                 run_dir);

    app::ProgressBar bar("replay (mission s)", 100);
    std::size_t shown = 0;
    const double end_s = std::isfinite(config.end_s) ? config.end_s : 0.0;
    const auto result = replayer.run(wall_start, [] { return app::shutdown_requested(); }, [&](double mission_s) {
      if (end_s <= 0.0) return;
      const auto percent = static_cast<std::size_t>(std::clamp(100.0 * (mission_s - config.start_s) / (end_s - config.start_s), 0.0, 100.0));
      if (percent > shown) {
        bar.tick(percent - shown);
        shown = percent;
      }
    });
    bar.finish();
    if (!result.read.damage.empty()) spdlog::warn("the recording is damaged: {}; replayed what could be read", result.read.damage);
    for (const auto& [topic, n] : result.published_by_topic) spdlog::info("  {}: {} published", topic, n);
    spdlog::info("replayed {} messages ({} filtered out, {} write failures, {} undecodable)", result.published, result.filtered,
                 result.write_failures, result.undecodable);
    if (!children.empty()) app::wait_for_shutdown(std::chrono::milliseconds(static_cast<int>(tail_s * 1000)));
    bool children_ok = true;
    // The nodes first, the recorder last (it finishes the file).
    for (auto it = children.rbegin(); it != children.rend(); ++it) {
      const int code = (*it)->stop(std::chrono::seconds(20));
      if (code != 0) {
        spdlog::error("{} ended with exit code {} (see {}/{}.log)", (*it)->name(), code, run_dir, (*it)->name());
        children_ok = false;
      }
    }
    if (!record_path.empty()) spdlog::info("replay recorded to {}", record_path);
    if (app::shutdown_requested()) return app::ExitCode::kInterrupted;
    return result.write_failures == 0 && children_ok ? app::ExitCode::kOk : app::ExitCode::kFailure;
  });
}
