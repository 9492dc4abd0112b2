// sarloc-bench-recorder: the largest rate sarloc-record keeps up with on this machine, without
// losing a sample, against what an incident of N responders produces (docs/benchmarks.md).
//
// For each offered rate: a fresh sarloc-record process, and a publisher of FieldMeasurement
// samples (the commonest input; 200 rescuers x 3 signals as instances) paced every millisecond
// for --seconds. Then the file is read back: every sample published must be in it.
// --reference RECORDING measures a mission's messages per responder and mission second and its
// bytes per message, and scales them to --responders.
//
// Exit codes: 0 measured; 2 bad command line; 3 bad options; 4 could not run.
#include <CLI/CLI.hpp>
#include <unistd.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "mission_record.hpp"
#include "sarloc/app/child_process.hpp"
#include "sarloc/app/command_line.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shipped_missions.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/writer.hpp"
#include "sarloc/recording/mcap_reader.hpp"

namespace fs = std::filesystem;

namespace {

double cpu_seconds_of(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const auto close = text.rfind(')');
  if (close == std::string::npos) return 0.0;
  std::istringstream fields(text.substr(close + 2));
  std::string field;
  double utime = 0, stime = 0;
  for (int k = 3; k <= 15 && fields >> field; ++k) {
    if (k == 14) utime = std::stod(field);
    if (k == 15) stime = std::stod(field);
  }
  return (utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

std::string cpu_model() {
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown CPU";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sarloc;
  CLI::App cli{"sarloc-bench-recorder: the largest rate sarloc-record records without loss"};
  std::vector<double> rates{1000, 2000, 5000, 10000, 20000, 40000};
  double seconds = 5.0;
  int domain = 163;
  std::string config_path = app::shipped_mission("default.yaml"), reference, log_level = "warn";
  int responders = 200;
  cli.add_option("--rates", rates, "offered rates, messages per second")->delimiter(',');
  cli.add_option("--seconds", seconds, "wall seconds per rate")->capture_default_str();
  cli.add_option("-c,--config", config_path,
                 std::string("mission YAML for the DDS profile and record: settings (default: default.yaml in ") +
                     app::kShippedMissionsHelp + ")");
  cli.add_option("--domain", domain, "DDS domain id")->capture_default_str();
  cli.add_option("--reference", reference, "a mission recording to scale to --responders");
  cli.add_option("--responders", responders, "incident size the reference is scaled to")->capture_default_str();
  app::add_log_level_option(cli, log_level);
  cli.set_version_flag("--version", SARLOC_VERSION);
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-bench-recorder", [&] {
    app::setup_logging(log_level, "bench");
    if (!(seconds > 0.5 && seconds < 600)) throw ConfigError("--seconds must be in (0.5, 600)");
    std::printf("machine: %s, %u hardware threads\n\n", cpu_model().c_str(), std::thread::hardware_concurrency());
    if (!reference.empty()) {
      const auto record = report::load_mission_record(reference);
      std::uint64_t messages = 0, bytes = 0;
      std::map<std::uint16_t, std::string> topics;
      recording::McapVisitor visitor;
      visitor.on_channel = [&](const recording::Channel& c) { topics[c.id] = c.topic; };
      visitor.on_message = [&](const recording::Message& m) {
        if (topics[m.channel_id].rfind("sarloc/recorder", 0) == 0) return;
        ++messages;
        bytes += m.data.size();
      };
      recording::read_mcap(reference, visitor);
      const double per_responder_s = static_cast<double>(messages) / record.duration_s / static_cast<double>(record.responders.size());
      const double per_message = static_cast<double>(bytes) / static_cast<double>(messages);
      std::printf("reference %s: %zu responders, %.0f mission s, %llu messages of %.0f B on average: %.2f messages per "
                  "responder per mission second\n=> %d responders in real time: %.0f messages/s, %.3f MB/s\n\n",
                  reference.c_str(), record.responders.size(), record.duration_s, static_cast<unsigned long long>(messages),
                  per_message, per_responder_s, responders, per_responder_s * responders,
                  per_responder_s * responders * per_message / 1e6);
    }
    const auto mission = app::load_mission_config(config_path);
    const fs::path bin_dir = fs::canonical("/proc/self/exe").parent_path();
    const fs::path dir = fs::temp_directory_path() / ("sarloc-bench-recorder-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    auto participant = std::make_shared<sarloc::dds::Participant>(
        app::participant_config(mission, domain, "bench-publisher", "bench-publisher"));
    sarloc::dds::Writer<::sarloc::FieldMeasurement> writer(participant);
    // The payload: a real measurement (its size as on the wire).
    avalanche::FieldMeasurement m;
    m.rescuer_id = "rescuer-000";
    m.stamp = 1;
    m.field = Vec3(1e-6, 2e-7, 3e-8);
    m.noise_stddev = Vec3(1e-8, 1e-8, 1e-8);
    m.valid_axes = 7;
    const std::size_t payload_bytes = sarloc::dds::encode_payload<::sarloc::FieldMeasurementPubSubType>(sarloc::dds::to_idl(m)).size();

    std::printf("| offered msg/s | published msg/s | payload MB/s | in the file | missing | lost (DDS) | recorder CPU %% | file MB/s | result |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    for (const double rate : rates) {
      const fs::path file = dir / ("rate-" + std::to_string(static_cast<long>(rate)) + ".mcap");
      app::ChildProcess recorder("record", {(bin_dir / "sarloc-record").string(), "-c", config_path, "--domain",
                                            std::to_string(domain), "-o", file.string(), "--log-level", "warn"},
                                 (dir / "record.log").string());
      if (!writer.wait_for_readers(1, std::chrono::seconds(15))) throw std::runtime_error("the recorder did not match");
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      const double cpu_before = cpu_seconds_of(recorder.pid());
      std::uint64_t published = 0, failed = 0;
      const auto start = std::chrono::steady_clock::now();
      const auto end = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
      std::uint64_t sequence = 0;
      for (auto tick = start; tick < end; tick += std::chrono::milliseconds(1)) {
        const auto due = static_cast<std::uint64_t>(rate * std::chrono::duration<double>(tick - start).count());
        while (published + failed < due) {
          ++sequence;
          m.rescuer_id = "rescuer-" + std::to_string(sequence % 200);
          m.signal_id = static_cast<std::uint32_t>(1 + (sequence / 200) % 3);
          m.sequence = sequence;
          if (writer.write(sarloc::dds::to_idl(m))) ++published; else ++failed;
        }
        std::this_thread::sleep_until(tick + std::chrono::milliseconds(1));
      }
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      writer.wait_for_acknowledgments(std::chrono::seconds(10));
      std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // past one flush period
      const double cpu = cpu_seconds_of(recorder.pid()) - cpu_before;
      recorder.stop(std::chrono::seconds(30));
      std::uint64_t in_file = 0, lost = 0;
      std::map<std::uint16_t, std::string> topics;
      recording::McapVisitor visitor;
      visitor.on_channel = [&](const recording::Channel& c) { topics[c.id] = c.topic; };
      visitor.on_message = [&](const recording::Message& msg) {
        if (topics[msg.channel_id] == "sarloc/field_measurement") ++in_file;
      };
      visitor.on_metadata = [&](const recording::Metadata& md) {
        if (md.name != "sarloc.recorder_counters" || !md.values.count("sarloc/field_measurement")) return;
        const std::string text = md.values.at("sarloc/field_measurement");
        const auto at = text.find("lost=");
        if (at != std::string::npos) lost = std::stoull(text.substr(at + 5));
      };
      recording::read_mcap(file.string(), visitor);
      const std::uint64_t missing = published > in_file ? published - in_file : 0;
      std::printf("| %.0f | %.0f | %.2f | %llu | %llu | %llu | %.0f | %.2f | %s |\n", rate, static_cast<double>(published) / elapsed,
                  static_cast<double>(published) * static_cast<double>(payload_bytes) / elapsed / 1e6,
                  static_cast<unsigned long long>(in_file), static_cast<unsigned long long>(missing),
                  static_cast<unsigned long long>(lost), 100.0 * cpu / elapsed,
                  static_cast<double>(fs::file_size(file)) / elapsed / 1e6,
                  missing == 0 && failed == 0 && lost == 0 ? "no loss" : "LOSS");
      std::fflush(stdout);
      fs::remove(file);
    }
    std::printf("\npayload: FieldMeasurement, %zu B each; %.1f s per rate; default record: settings (zstd, flush 1 s)\n",
                payload_bytes, seconds);
    fs::remove_all(dir);
    return app::ExitCode::kOk;
  });
}
