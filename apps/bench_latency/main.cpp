// sarloc-bench-latency: end-to-end latency of the localization core daemon under load.
//
// Starts sarloc-core as its own process, then simulates N rescuers in this process (one DDS
// participant, as N devices' traffic) publishing odometry and field samples at `rate` Hz, each
// rescuer on its own phase within the period (devices are not synchronised). Latency = wall
// time from a measurement's publication to the arrival of the matching VictimEstimate
// (same rescuer, signal and sequence) at the rescuer side. The daemon's CPU and memory come
// from its NodeStatus. docs/benchmarks.md has the measured table.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include "sarloc/app/command_line.hpp"
#include "sarloc/app/child_process.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/core/avalanche/evaluation.hpp"
#include "sarloc/app/mission_config.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/progress_bar.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/mission/simulated_rescuer.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"

namespace {

using namespace sarloc;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct LoadResult {
  std::size_t rescuers = 0;
  double rate_hz = 0.0;
  std::size_t measurements = 0;
  std::size_t answered = 0;
  double p50_ms = -1.0;
  double p99_ms = -1.0;
  double max_ms = -1.0;
  double cpu_percent = -1.0;  ///< daemon, mean over the run (% of one core)
  double rss_mb = -1.0;       ///< daemon, peak
};


// Rescuers spread over the debris so that each hears one to three victims.
mission::MissionScenario bench_scenario(const app::MissionConfig& mission, std::size_t n, std::uint64_t seed,
                                        const std::string& prefix) {
  mission::MissionScenario s = mission.scenario;
  s.rescuers.clear();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Vec3 centre = Vec3::Zero();
  for (const auto& v : s.victims) centre += v.position / static_cast<double>(s.victims.size());
  for (std::size_t i = 0; i < n; ++i) {
    const double r = 25.0 + 25.0 * u(rng);
    const double a = 2.0 * M_PI * u(rng);
    s.rescuers.push_back({prefix + std::to_string(i), "bench",
                          Vec3(centre.x() + r * std::cos(a), centre.y() + r * std::sin(a), 0.0), 360.0 * u(rng)});
  }
  s.seed = seed;
  return s;
}

LoadResult run_load(const app::MissionConfig& mission, const std::string& bin_dir, const std::string& config_path,
                    std::uint32_t domain, std::size_t n, double rate_hz, double duration_s, const std::string& log_dir,
                    std::uint64_t seed) {
  LoadResult result;
  result.rescuers = n;
  result.rate_hz = rate_hz;
  // A fresh daemon per load point: nothing left over from the previous one.
  app::ChildProcess daemon("sarloc-core",
                           {bin_dir + "/sarloc-core", "-c", config_path, "--domain", std::to_string(domain),
                            "--log-level", "warn"},
                           log_dir + "/core-" + std::to_string(n) + "-" + std::to_string(rate_hz) + ".log");

  auto participant = std::make_shared<sarloc::dds::Participant>(
      app::participant_config(mission, static_cast<int>(domain), "bench-rescuers"));
  sarloc::dds::Writer<::sarloc::FieldMeasurement> measurements(participant);
  sarloc::dds::Writer<::sarloc::Odometry> odometry(participant);

  std::mutex mutex;
  std::map<std::tuple<std::string, std::uint32_t, std::uint64_t>, Clock::time_point> sent;
  std::vector<double> latencies;
  std::vector<double> cpu;
  double rss = -1.0;
  sarloc::dds::Reader<::sarloc::VictimEstimate> estimates(participant, [&](const ::sarloc::VictimEstimate& e, const auto&) {
    const auto now = Clock::now();
    std::lock_guard<std::mutex> lock(mutex);
    const auto it = sent.find({e.rescuer_id().to_string(), e.signal_id(), e.measurement_sequence()});
    if (it == sent.end()) return;
    latencies.push_back(std::chrono::duration<double, std::milli>(now - it->second).count());
    sent.erase(it);
  });
  sarloc::dds::Reader<::sarloc::NodeStatus> status(participant, [&](const ::sarloc::NodeStatus& s, const auto&) {
    if (s.kind() != ::sarloc::NODE_CORE) return;
    std::lock_guard<std::mutex> lock(mutex);
    cpu.push_back(s.cpu_percent());
    rss = std::max(rss, s.rss_mb());
  });
  if (!measurements.wait_for_readers(1, std::chrono::seconds(10)) || !odometry.wait_for_readers(1, std::chrono::seconds(10)) ||
      !estimates.wait_for_writers(1, std::chrono::seconds(10))) {
    throw Error("sarloc-core did not come up on domain " + std::to_string(domain));
  }

  const auto scenario = bench_scenario(mission, n, seed, "bench-" + std::to_string(n) + "-");
  std::vector<mission::SimulatedRescuer> sims;
  for (const auto& r : scenario.rescuers) sims.emplace_back(scenario, r.id);
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
  const auto start = Clock::now() + std::chrono::milliseconds(200);
  const std::size_t epochs = static_cast<std::size_t>(duration_s * rate_hz);
  const TimestampNs t0 = sarloc::dds::MissionClock::wall_now_ns();
  const auto period_ns = static_cast<TimestampNs>(1e9 / rate_hz);
  app::ProgressBar bar(std::to_string(n) + " rescuers @ " + std::to_string(rate_hz).substr(0, 4) + " Hz", epochs * n);
  // Every rescuer on its own phase; walk straight on (the guidance is not the point here).
  for (std::size_t k = 0; k < epochs && !app::shutdown_requested(); ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      const auto due = start + k * period + (period * static_cast<long>(i)) / static_cast<long>(n);
      std::this_thread::sleep_until(due);
      // Integer stamps: one step's end is exactly the next one's start.
      const auto stamp_of = [&](std::size_t epoch) {
        return t0 + static_cast<TimestampNs>(epoch) * period_ns + period_ns * static_cast<TimestampNs>(i) / static_cast<TimestampNs>(n);
      };
      const TimestampNs stamp = stamp_of(k);
      auto& sim = sims[i];
      if (k > 0) odometry.write(sarloc::dds::to_idl(sim.walk(0.0, 1.0 / rate_hz, stamp_of(k - 1), stamp)));
      for (const auto& m : sim.measure(stamp)) {
        {
          std::lock_guard<std::mutex> lock(mutex);
          sent[{m.rescuer_id, m.signal_id, m.sequence}] = Clock::now();
        }
        measurements.write(sarloc::dds::to_idl(m));
        ++result.measurements;
      }
      bar.tick();
    }
  }
  bar.finish();
  std::this_thread::sleep_for(std::chrono::seconds(1));  // stragglers
  std::lock_guard<std::mutex> lock(mutex);
  result.answered = latencies.size();
  if (!latencies.empty()) {  // otherwise -1: no answer at all
    result.p50_ms = avalanche::percentile(latencies, 0.5);
    result.p99_ms = avalanche::percentile(latencies, 0.99);
    result.max_ms = avalanche::percentile(latencies, 1.0);
  }
  if (cpu.size() > 2) {
    // The first status covers start-up; the mean of the rest is the load's.
    double sum = 0.0;
    for (std::size_t i = 1; i < cpu.size(); ++i) sum += cpu[i];
    result.cpu_percent = sum / static_cast<double>(cpu.size() - 1);
  }
  result.rss_mb = rss;
  daemon.stop(std::chrono::seconds(5));
  return result;
}

nlohmann::json to_json(const LoadResult& r) {
  return {{"rescuers", r.rescuers}, {"rate_hz", r.rate_hz},   {"measurements", r.measurements},
          {"answered", r.answered}, {"p50_ms", r.p50_ms},     {"p99_ms", r.p99_ms},
          {"max_ms", r.max_ms},     {"cpu_percent", r.cpu_percent}, {"rss_mb", r.rss_mb}};
}

void print_row(const LoadResult& r) {
  std::printf("%9zu %8.1f %10zu %9zu %9.1f %9.1f %9.1f %9.0f %9.1f\n", r.rescuers, r.rate_hz, r.measurements, r.answered,
              r.p50_ms, r.p99_ms, r.max_ms, r.cpu_percent, r.rss_mb);
}

}  // namespace

int main(int argc, char** argv) {
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-bench-latency: measurement -> estimate latency of sarloc-core under load"};
  std::string config_path = SARLOC_SOURCE_DIR "/config/missions/default.yaml";
  std::vector<std::size_t> loads{1, 10, 50};
  double rate = 1.0;
  double duration = 30.0;
  std::size_t search_rescuers = 50;
  std::vector<double> search_rates{1, 2, 4, 6, 8, 12, 16};
  double p99_limit_ms = 100.0;
  bool search = true;
  int domain = 60;
  std::uint64_t seed = 1;
  std::string json_path;
  std::string log_level = "warn";
  cli.add_option("-c,--config", config_path, "mission YAML (victims, sensors, filter parameters)")->capture_default_str();
  cli.add_option("--rescuers", loads, "load points: numbers of simulated rescuers (e.g. 1,10,50)")->delimiter(',')->capture_default_str();
  cli.add_option("--rate", rate, "measurement rate of the load points (Hz)")->capture_default_str();
  cli.add_option("--duration", duration, "seconds per load point")->capture_default_str();
  cli.add_option("--search-rescuers", search_rescuers, "rescuers for the highest-rate search")->capture_default_str();
  cli.add_option("--search-rates", search_rates, "rates tried, increasing, until p99 exceeds the limit (e.g. 1,2,4)")->delimiter(',')->capture_default_str();
  cli.add_option("--p99-limit-ms", p99_limit_ms, "the p99 bound of the rate search")->capture_default_str();
  cli.add_flag("!--no-search", search, "skip the highest-rate search");
  cli.add_option("--domain", domain, "DDS domain id")->capture_default_str();
  cli.add_option("--seed", seed, "seed of the rescuers' placement and noise")->capture_default_str();
  cli.add_option("--json", json_path, "write the figures as JSON here");
  app::add_log_level_option(cli, log_level);
  cli.set_version_flag("--version", SARLOC_VERSION);
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-bench-latency", [&] {
    app::setup_logging(log_level, "bench");
    if (!(rate > 0.0 && rate <= 100.0)) throw ConfigError("--rate = " + std::to_string(rate) + ": must be in (0, 100]");
    if (!(duration >= 2.0)) throw ConfigError("--duration = " + std::to_string(duration) + ": must be >= 2 s");
    const auto mission = app::load_mission_config(config_path);
    const std::string bin_dir = fs::canonical("/proc/self/exe").parent_path().string();
    const std::string log_dir = (fs::temp_directory_path() / ("sarloc-bench-" + std::to_string(getpid()))).string();
    fs::create_directories(log_dir);
    const std::string config_abs = fs::absolute(config_path).string();

    nlohmann::json out;
    out["loads"] = nlohmann::json::array();
    std::printf("%9s %8s %10s %9s %9s %9s %9s %9s %9s\n", "rescuers", "rate Hz", "measured", "answered", "p50 ms",
                "p99 ms", "max ms", "cpu %", "rss MB");
    for (const auto n : loads) {
      const auto r = run_load(mission, bin_dir, config_abs, static_cast<std::uint32_t>(domain), n, rate, duration, log_dir, seed);
      print_row(r);
      out["loads"].push_back(to_json(r));
      if (app::shutdown_requested()) return app::ExitCode::kInterrupted;
    }
    if (search) {
      std::printf("\nhighest rate with %zu rescuers and p99 < %.0f ms:\n", search_rescuers, p99_limit_ms);
      double best = 0.0;
      out["rate_search"] = nlohmann::json::array();
      for (const double r_hz : search_rates) {
        const auto r = run_load(mission, bin_dir, config_abs, static_cast<std::uint32_t>(domain), search_rescuers, r_hz,
                                std::max(10.0, duration / 2.0), log_dir, seed);
        print_row(r);
        out["rate_search"].push_back(to_json(r));
        const bool ok = r.p99_ms >= 0.0 && r.p99_ms < p99_limit_ms && r.answered * 100 >= r.measurements * 99;
        if (!ok || app::shutdown_requested()) break;
        best = r_hz;
      }
      std::printf("=> %.1f Hz\n", best);
      out["highest_rate_hz"] = best;
    }
    if (!json_path.empty()) std::ofstream(json_path) << out.dump(2) << "\n";
    return app::ExitCode::kOk;
  });
}
