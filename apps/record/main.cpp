// sarloc-record: records every sarloc topic of a mission into an MCAP file (docs/operations/
// recording.md), or, with --recover, rewrites a recording that a crash cut short.
//
// Exit codes: 0 recorded until stopped (SIGINT/SIGTERM or --duration) and the file is whole,
// or --recover succeeded; 2 bad command line; 3 bad mission file; 4 could not record (DDS,
// unwritable path, disk full: the message names the file) or the file is not MCAP.
#include <CLI/CLI.hpp>

#include "sarloc/core/common/validate.hpp"
#include <spdlog/spdlog.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sarloc/app/command_line.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/redact_secrets.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/dds/recorder.hpp"
#include "sarloc/recording/mcap_recovery.hpp"

namespace {

using sarloc::ConfigError;

// "KEY=VALUE" -> (KEY, VALUE); ConfigError naming the option otherwise.
std::pair<std::string, std::string> split_pair(const std::string& option, const std::string& text) {
  const auto equals = text.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw ConfigError(option + " '" + text + "': expected KEY=VALUE");
  }
  return {text.substr(0, equals), text.substr(equals + 1)};
}

std::string read_text_file(const std::string& option, const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw ConfigError(option + ": cannot read '" + path + "'");
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

std::string counters_line(const std::map<std::string, sarloc::dds::TopicCounters>& counters) {
  std::uint64_t received = 0, written = 0, lost = 0, rejected = 0;
  for (const auto& [name, c] : counters) {
    received += c.received;
    written += c.written;
    lost += c.lost;
    for (const auto& [reason, n] : c.rejected) rejected += n;
  }
  return std::to_string(received) + " received, " + std::to_string(written) + " written, " + std::to_string(lost) +
         " lost, " + std::to_string(rejected) + " rejected";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sarloc;
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-record: record every sarloc topic into an MCAP file, or --recover one"};
  std::string config_path, output, directory, recover_path, log_level = "info", prefix;
  int domain = -1;
  double duration_s = 0.0;
  std::vector<std::string> meta, meta_files;
  cli.add_option("-c,--config", config_path, "mission YAML: its dds: and record: sections");
  cli.add_option("-o,--output", output, "the .mcap file to write (default: <record.directory>/<mission>-<UTC time>.mcap)");
  cli.add_option("--directory", directory, "folder for the default file name, overriding record.directory");
  cli.add_option("--domain", domain, "DDS domain id, overriding dds.domain_id of the config");
  cli.add_option("--duration", duration_s, "stop after this many seconds (default: at SIGINT/SIGTERM)");
  cli.add_option("--meta", meta, "KEY=VALUE written into the recording's sarloc.recording metadata (repeatable)");
  cli.add_option("--meta-file", meta_files, "KEY=PATH: the file's text as metadata KEY (repeatable)");
  cli.add_option("--recover", recover_path, "rewrite this cut-short or damaged recording with a proper summary, and exit");
  app::add_log_level_option(cli, log_level);
  cli.set_version_flag("--version", SARLOC_VERSION);
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-record", [&] {
    app::setup_logging(log_level, "record");
    if (!recover_path.empty()) {
      const auto result = recording::recover_mcap(recover_path);
      if (result.was_complete) {
        spdlog::info("'{}' is whole ({} messages): nothing to recover", recover_path, result.messages);
      } else {
        spdlog::warn("'{}' recovered: {} messages kept, {} bytes could not be read ({}); the original is kept as '{}.damaged'",
                     recover_path, result.messages, result.bytes_lost, result.damage, recover_path);
      }
      return app::ExitCode::kOk;
    }
    if (config_path.empty()) throw ConfigError("-c/--config is required (or --recover FILE)");
    if (duration_s < 0.0) throw ConfigError("--duration = " + config_value(duration_s) + ": must be >= 0");
    const auto mission = app::load_mission_config(config_path);
    sarloc::dds::RecorderConfig config = mission.record;
    config.output_path = output.empty()
                             ? sarloc::dds::timestamped_recording_path(directory.empty() ? mission.record_directory : directory, mission.name)
                             : output;
    config.metadata["mission"] = mission.name;
    config.metadata["mission_file"] = config_path;
    config.metadata["software"] = std::string("sarloc ") + SARLOC_VERSION;
    config.metadata["domain_id"] = std::to_string(domain >= 0 ? domain : static_cast<int>(mission.dds.domain_id));
    for (const auto& m : meta) config.metadata.insert(split_pair("--meta", m));
    for (const auto& m : meta_files) {
      const auto [key, path] = split_pair("--meta-file", m);
      config.metadata[key] = app::redact_secrets(read_text_file("--meta-file " + key, path));
    }
    auto participant = std::make_shared<sarloc::dds::Participant>(
        app::participant_config(mission, domain, "sarloc-record", app::kRecorderIdentity));
    sarloc::dds::Recorder recorder(participant, config);
    spdlog::info("recording {} topic(s) of mission '{}' to '{}' (flush every {} s)", recorder.counters().size(),
                 mission.name, config.output_path, config.flush_period_s);
    const auto start = std::chrono::steady_clock::now();
    auto last_log = start;
    while (!app::wait_for_shutdown(std::chrono::milliseconds(100))) {
      if (!recorder.error().empty()) break;
      const auto now = std::chrono::steady_clock::now();
      if (duration_s > 0 && std::chrono::duration<double>(now - start).count() >= duration_s) break;
      if (now - last_log >= std::chrono::seconds(10)) {
        spdlog::info("recording: {}", counters_line(recorder.counters()));
        last_log = now;
      }
    }
    recorder.close();  // throws RecordingError (exit 4) if the file could not be written
    std::string files;
    for (const auto& f : recorder.files()) files += " " + f;
    spdlog::info("recording complete: {}; file(s):{}", counters_line(recorder.counters()), files);
    return app::ExitCode::kOk;
  });
}
