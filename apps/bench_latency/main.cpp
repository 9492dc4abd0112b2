// sarloc-bench-latency: end-to-end latency of the localization core daemon under load, against
// a raw DDS echo.
//
// For each load point it starts a responder as its own process, then simulates N rescuers in
// this process (one DDS participant, as N devices' traffic) publishing odometry and field
// samples at `rate` Hz, each rescuer on its own phase within the period (devices are not
// synchronised). Latency = wall time from a measurement's publication to the arrival of the
// matching VictimEstimate (same rescuer, signal and sequence) at the rescuer side.
//
// Responders ("targets"): sarloc-core, and sarloc-bench-echo (echo_node.hpp), which answers every
// measurement at once on the same participant, topic and QoS profiles: the floor of what DDS
// costs on this machine. Both run at every load point, interleaved, `--repeat` times; the
// summary gives the medians over the repeats side by side, with the ratio sarloc/echo.
// The responders' CPU and memory come from their NodeStatus. docs/benchmarks.md has the tables.
//
// Each load point's responder reads a copy of the mission file whose rescuers are the bench's
// (so the daemon's roster admits them; `--admission open` admits any id instead). For soaks,
// the responder's resident memory is followed over the run (RSS at 20-30 % of it, at the end,
// and its slope over the second half). `--intruder-ids N` adds a hostile publisher on its own
// participant: field samples and odometry cycling through N rescuer ids that no one serves,
// at `--intruder-rate` samples per second, while the real rescuers are measured.
// `--firefighters N` (sarloc-core only; the mission needs a building: section) adds N firefighters
// searching its building at about 2 steps a second (firefighter_crew.hpp), in the same run and
// on the same daemon: the odometry step -> map-aided position latency is reported beside the
// rescuers' (issue 64, a mixed incident).
#include <spdlog/spdlog.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <thread>

#include "echo_node.hpp"
#include "firefighter_crew.hpp"
#include "intruder.hpp"
#include "sarloc/app/child_process.hpp"
#include "sarloc/app/command_line.hpp"
#include "sarloc/app/json_io.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/mission_config.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/progress_bar.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shipped_missions.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/avalanche/receiver_model.hpp"
#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/statistics.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/mission/simulated_rescuer.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/process_stats.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"

namespace {

using namespace sarloc;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

enum class Target { kEcho, kSarloc };

const char* to_string(Target t) { return t == Target::kEcho ? "echo" : "sarloc"; }

Target parse_target(const std::string& text) {
  if (text == "echo") return Target::kEcho;
  if (text == "sarloc") return Target::kSarloc;
  throw ConfigError("--targets contains '" + text + "': must be echo or sarloc");
}

/// What every run shares.
struct BenchSetup {
  app::MissionConfig mission;
  std::string bin_dir;
  std::string config_path;  ///< absolute
  std::string core_exe;     ///< the daemon's executable (default: sarloc-core next to this one)
  std::uint32_t domain = 60;
  std::string log_dir;
  std::uint64_t seed = 1;
  bench::EchoHandoff echo_handoff = bench::EchoHandoff::kListener;
  std::string trace_dir;  ///< per-sample CSV of every run here, if set
  /// Seconds of load published before measuring starts. The daemon's filters start at ~1700
  /// mixture components and prune over the first tens of epochs: without a warm-up the bench
  /// measures that opening phase, with one it measures later, smaller mixtures.
  double warmup_s = 0.0;
  std::string admission = "roster";  ///< core.admission of the responder's config copy
  std::size_t intruder_ids = 0;      ///< distinct ids of the hostile publisher (0: none)
  double intruder_rate = 1000.0;     ///< its samples per second
  bool intruder_odometry = true;     ///< odometry as well as field samples
  /// Rescuers circle the debris instead of walking straight on: they stay in range of the
  /// victims however long the run (soaks); straight on, they leave it after 1-2 minutes.
  bool circle = false;
  /// The simulated devices' receiver, when not the mission file's. The daemon sees field
  /// samples either way; the realistic receiver separates every device's pulses in this
  /// process (about 0.6 % of a core per rescuer at 1 Hz), so at hundreds of rescuers the load
  /// generator falls behind its schedule and takes CPU from the daemon it measures.
  std::optional<avalanche::ReceiverKind> receiver;
  /// Firefighters in every sarloc-core run (null: none), made once: their walks take a while.
  std::shared_ptr<const bench::FirefighterCrew> crew;
};

struct LoadResult {
  Target target = Target::kSarloc;
  std::size_t repeat = 0;
  std::size_t rescuers = 0;
  double rate_hz = 0.0;
  std::size_t measurements = 0;
  std::size_t answered = 0;
  double p50_ms = -1.0;
  double p99_ms = -1.0;
  double max_ms = -1.0;
  /// Medians of the two legs, split at the answer's DDS source timestamp (the responder's
  /// write() call): publication -> answer written (inbound DDS + the responder's own time),
  /// answer written -> arrival here (outbound DDS and this process's listener).
  double to_write_p50_ms = -1.0;
  double return_p50_ms = -1.0;
  double cpu_percent = -1.0;  ///< responder, mean over the run (% of one core)
  double rss_mb = -1.0;       ///< responder, peak
  double rss_early_mb = -1.0;          ///< responder, median RSS over 20-30 % of the measured run
  double rss_end_mb = -1.0;            ///< median over its last 10 %
  double rss_growth_mb_per_min = 0.0;  ///< least-squares slope over its second half
  std::uint64_t refused = 0;           ///< samples the responder refused (its last NodeStatus)
  std::uint64_t accepted = 0;          ///< samples (field and odometry) it accepted (its last NodeStatus)
  std::uint64_t published = 0;         ///< samples (field and odometry) this bench's rescuers wrote
  std::size_t intruder_sent = 0;       ///< samples the hostile publisher wrote
  /// How late the load generator published against its schedule over the measured phase:
  /// each rescuer's epoch is due at a fixed time; a lag that grows means it cannot keep up.
  double lag_p99_ms = -1.0;
  double lag_max_ms = -1.0;
  double bench_cpu_percent = -1.0;  ///< this process (load generator and its DDS), measured phase
  std::size_t firefighters = 0;     ///< in this run (sarloc-core with --firefighters)
  std::size_t ff_steps = 0;         ///< odometry steps they published in the measured phase
  std::size_t ff_answered = 0;      ///< of those, answered with a map-aided position
  double ff_p50_ms = -1.0;          ///< step -> position
  double ff_p99_ms = -1.0;
  double ff_max_ms = -1.0;
};

/// One measurement's times, steady clock ns (-1: did not happen).
struct SampleTimes {
  std::int64_t published = -1;       ///< just before write()
  std::int64_t write_returned = -1;  ///< write() returned
  std::int64_t answer_written = -1;  ///< the answer's source timestamp (responder's write())
  std::int64_t answer_received = -1; ///< the answer's reception timestamp (Fast DDS, here)
  std::int64_t answered = -1;        ///< our listener got the answer
};

std::int64_t steady_ns(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

Vec3 centre_of_victims(const mission::MissionScenario& s) {
  Vec3 centre = Vec3::Zero();
  for (const auto& v : s.victims) centre += v.position / static_cast<double>(s.victims.size());
  return centre;
}

// Rescuers spread over the debris so that each hears one to three victims.
mission::MissionScenario bench_scenario(const app::MissionConfig& mission, std::size_t n, std::uint64_t seed,
                                        const std::string& prefix,
                                        const std::optional<avalanche::ReceiverKind>& receiver) {
  mission::MissionScenario s = mission.scenario;
  if (receiver) s.sensors.receiver.kind = *receiver;
  s.rescuers.clear();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 centre = centre_of_victims(s);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = 25.0 + 25.0 * u(rng);
    const double a = 2.0 * sarloc::kPi * u(rng);
    s.rescuers.push_back({prefix + std::to_string(i), "bench",
                          Vec3(centre.x() + r * std::cos(a), centre.y() + r * std::sin(a), 0.0), 360.0 * u(rng)});
  }
  s.seed = seed;
  return s;
}

/// The mission file with the bench's rescuers in place of its own (and no sectors), so that
/// the daemon's roster serves exactly them; returns its path.
std::string write_bench_config(const BenchSetup& setup, const mission::MissionScenario& scenario,
                               const bench::FirefighterCrew* crew, const std::string& path) {
  YAML::Node doc = YAML::LoadFile(setup.config_path);
  doc.remove("sectors");
  YAML::Node rescuers(YAML::NodeType::Sequence);
  for (const auto& r : scenario.rescuers) {
    YAML::Node n;
    n["id"] = r.id;
    n["team"] = r.team;
    n["start"].push_back(r.start.x());
    n["start"].push_back(r.start.y());
    n["heading_deg"] = r.heading_deg;
    rescuers.push_back(n);
  }
  if (crew) crew->write_roster(rescuers);
  doc["rescuers"] = rescuers;
  doc["core"]["admission"] = setup.admission;
  doc["dds"]["profiles_file"] = fs::absolute(setup.mission.dds.profiles_file).string();
  doc["dds"]["topics_file"] = fs::absolute(setup.mission.dds.topics_file).string();
  // The copy lives elsewhere: the building's plan as the original file names it.
  if (doc["building"] && doc["building"]["plan"]) {
    const fs::path plan = doc["building"]["plan"].as<std::string>();
    if (plan.is_relative()) doc["building"]["plan"] = (fs::path(setup.config_path).parent_path() / plan).string();
  }
  std::ofstream out(path);
  out << doc << '\n';
  if (!out) throw Error("cannot write the bench's mission copy '" + path + "'");
  return path;
}

/// Median of the values whose time lies in [from, to).
double median_between(const std::vector<std::pair<double, double>>& series, double from, double to) {
  std::vector<double> v;
  for (const auto& [t, x] : series) {
    if (t >= from && t < to) v.push_back(x);
  }
  return v.empty() ? -1.0 : sarloc::percentile(v, 0.5);
}

/// Least-squares slope (per unit of t) of the values with t >= from; 0 with fewer than 3.
double slope_after(const std::vector<std::pair<double, double>>& series, double from) {
  double n = 0, st = 0, sx = 0, stt = 0, stx = 0;
  for (const auto& [t, x] : series) {
    if (t < from) continue;
    n += 1;
    st += t;
    sx += x;
    stt += t * t;
    stx += t * x;
  }
  const double den = n * stt - st * st;
  return n >= 3 && den > 0.0 ? (n * stx - st * sx) / den : 0.0;
}

/// The responder process and the node_id its NodeStatus carries.
std::pair<std::unique_ptr<app::ChildProcess>, std::string> start_target(const BenchSetup& setup, Target target,
                                                                       const std::string& config_path,
                                                                       const std::string& log_path) {
  const std::string domain = std::to_string(setup.domain);
  if (target == Target::kEcho) {
    return {std::make_unique<app::ChildProcess>(
                "sarloc-bench-echo",
                std::vector<std::string>{setup.bin_dir + "/sarloc-bench-echo", "-c", config_path, "--domain", domain,
                                         "--handoff", bench::to_string(setup.echo_handoff), "--log-level", "warn"},
                log_path),
            bench::EchoNodeConfig{}.node_id};
  }
  return {std::make_unique<app::ChildProcess>(
              "sarloc-core",
              std::vector<std::string>{setup.core_exe, "-c", config_path, "--domain", domain,
                                       "--log-level", "warn"},
              log_path),
          setup.mission.core_config("").node_id};
}

void write_trace(const std::string& path,
                 const std::map<std::tuple<std::string, std::uint32_t, std::uint64_t>, SampleTimes>& samples) {
  std::ofstream out(path);
  out << "rescuer_id,signal_id,sequence,published_ns,write_returned_ns,answer_written_ns,answer_received_ns,answered_ns\n";
  for (const auto& [key, t] : samples) {
    out << std::get<0>(key) << ',' << std::get<1>(key) << ',' << std::get<2>(key) << ',' << t.published << ','
        << t.write_returned << ',' << t.answer_written << ',' << t.answer_received << ',' << t.answered << '\n';
  }
  if (!out) throw Error("cannot write the trace '" + path + "'");
}

LoadResult run_load(const BenchSetup& setup, Target target, std::size_t repeat, std::size_t n, double rate_hz,
                    double duration_s) {
  LoadResult result;
  result.target = target;
  result.repeat = repeat;
  result.rescuers = n;
  result.rate_hz = rate_hz;
  const std::string run_name = std::string(to_string(target)) + "-" + std::to_string(n) + "-" +
                               std::to_string(rate_hz).substr(0, 4) + "-" + std::to_string(repeat);
  const auto scenario =
      bench_scenario(setup.mission, n, setup.seed, "bench-" + std::to_string(n) + "-", setup.receiver);
  // Firefighters are served by sarloc-core only (the echo answers measurements).
  const bench::FirefighterCrew* crew = target == Target::kSarloc ? setup.crew.get() : nullptr;
  result.firefighters = crew ? crew->size() : 0;
  // A fresh responder per load point: nothing left over from the previous one.
  auto [responder, responder_id] =
      start_target(setup, target, write_bench_config(setup, scenario, crew, setup.log_dir + "/" + run_name + ".yaml"),
                   setup.log_dir + "/" + run_name + ".log");

  auto participant = std::make_shared<sarloc::dds::Participant>(
      app::participant_config(setup.mission, static_cast<int>(setup.domain), "bench-rescuers", "bench-rescuers"));
  sarloc::dds::Writer<::sarloc::FieldMeasurement> measurements(participant);
  sarloc::dds::Writer<::sarloc::Odometry> odometry(participant);
  // The firefighters' own positions, as their devices publish them (firefighter_crew.hpp).
  std::optional<sarloc::dds::Writer<::sarloc::ResponderPosition>> reckonings;
  if (crew) reckonings.emplace(participant, sarloc::dds::device_position_options());

  // DDS stamps samples with the real-time clock; this run's offset maps them to steady time.
  const std::int64_t realtime_minus_steady =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count() -
      steady_ns(Clock::now());
  std::mutex mutex;
  std::map<std::tuple<std::string, std::uint32_t, std::uint64_t>, SampleTimes> samples;
  std::vector<double> cpu;
  double rss = -1.0;
  std::vector<std::pair<double, double>> rss_series;  // (steady s, MB)
  std::uint64_t refused = 0;
  std::uint64_t accepted = 0;
  sarloc::dds::Reader<::sarloc::VictimEstimate> estimates(
      participant, [&](const ::sarloc::VictimEstimate& e, const eprosima::fastdds::dds::SampleInfo& info) {
        const std::int64_t now = steady_ns(Clock::now());
        std::lock_guard<std::mutex> lock(mutex);
        const auto it = samples.find({e.rescuer_id().to_string(), e.signal_id(), e.measurement_sequence()});
        if (it == samples.end() || it->second.answered >= 0) return;  // not ours, or answered already
        it->second.answered = now;
        it->second.answer_written = info.source_timestamp.to_ns() - realtime_minus_steady;
        it->second.answer_received = info.reception_timestamp.to_ns() - realtime_minus_steady;
      });
  // Firefighters' steps by (responder, the step's end stamp): published, answered (steady ns).
  std::map<std::pair<std::string, TimestampNs>, std::pair<std::int64_t, std::int64_t>> steps;
  sarloc::dds::Reader<::sarloc::ResponderPosition> positions(
      participant, [&](const ::sarloc::ResponderPosition& p, const eprosima::fastdds::dds::SampleInfo&) {
        if (p.source() != ::sarloc::POSITION_MAP_AIDED) return;  // the crew's own reckoning, not an answer
        const std::int64_t now = steady_ns(Clock::now());
        std::lock_guard<std::mutex> lock(mutex);
        const auto it = steps.find({p.responder_id().to_string(), p.stamp()});
        if (it != steps.end() && it->second.second < 0) it->second.second = now;
      });
  sarloc::dds::Reader<::sarloc::NodeStatus> status(participant, [&](const ::sarloc::NodeStatus& s, const auto&) {
    if (s.node_id().to_string() != responder_id) return;
    std::lock_guard<std::mutex> lock(mutex);
    cpu.push_back(s.cpu_percent());
    rss = std::max(rss, s.rss_mb());
    rss_series.emplace_back(1e-9 * static_cast<double>(steady_ns(Clock::now())), s.rss_mb());
    refused = s.samples_rejected();
    accepted = s.samples_accepted();
  });
  if (!measurements.wait_for_readers(1, std::chrono::seconds(10)) ||
      !odometry.wait_for_readers(1, std::chrono::seconds(10)) ||
      !estimates.wait_for_writers(1, std::chrono::seconds(10))) {
    throw Error(std::string(responder->name()) + " did not come up on domain " + std::to_string(setup.domain));
  }

  std::vector<mission::SimulatedRescuer> sims;
  for (const auto& r : scenario.rescuers) sims.emplace_back(scenario, r.id);
  const Vec3 centre = centre_of_victims(scenario);
  std::unique_ptr<bench::Intruder> intruder;
  if (setup.intruder_ids > 0) {
    // A real-looking field sample: the first a bench rescuer takes (its own sim, left untouched).
    std::optional<avalanche::FieldMeasurement> field;
    for (const auto& r : scenario.rescuers) {
      mission::SimulatedRescuer probe(scenario, r.id);
      const auto ms = probe.measure(sarloc::dds::MissionClock::wall_now_ns());
      if (!ms.empty()) {
        field = ms.front();
        break;
      }
    }
    if (!field) throw Error("no bench rescuer hears a victim: nothing for the intruder to imitate");
    intruder = std::make_unique<bench::Intruder>(
        app::participant_config(setup.mission, static_cast<int>(setup.domain), "bench-intruder", "bench-intruder"),
        bench::IntruderOptions{setup.intruder_ids, setup.intruder_rate, setup.intruder_odometry, setup.log_dir},
        *field);
    if (!intruder->wait_for_daemon()) throw Error("the intruder did not match " + std::string(responder->name()));
  }
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
  const auto start = Clock::now() + std::chrono::milliseconds(200);
  const std::size_t warmup_epochs = static_cast<std::size_t>(setup.warmup_s * rate_hz);
  const std::size_t epochs = warmup_epochs + static_cast<std::size_t>(duration_s * rate_hz);
  const TimestampNs t0 = sarloc::dds::MissionClock::wall_now_ns();
  const auto period_ns = static_cast<TimestampNs>(1e9 / rate_hz);
  const double measure_from_s = 1e-9 * static_cast<double>(steady_ns(start)) + setup.warmup_s;
  const double measure_to_s = measure_from_s + duration_s;
  if (intruder) {  // from the start of the measured phase: the rescuers are served by then if warmed up
    const auto seconds = [](double s) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); };
    intruder->start(start + seconds(setup.warmup_s), start + seconds(setup.warmup_s + duration_s));
  }
  // The firefighters on a thread of their own: each step when its stride ends, from `start`.
  std::thread crew_thread;
  std::atomic<std::uint64_t> crew_published{0};
  if (crew) {
    crew_thread = std::thread([&, crew, t0] {
      const double end_s = setup.warmup_s + duration_s;
      for (const auto& step : crew->schedule()) {
        if (step.at_s > end_s || app::shutdown_requested()) break;
        std::this_thread::sleep_until(
            start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(step.at_s)));
        auto o = step.odometry;
        o.interval_start += t0;
        o.interval_end += t0;
        const bool measured = step.at_s >= setup.warmup_s;
        if (measured) {
          std::lock_guard<std::mutex> lock(mutex);
          steps[{o.rescuer_id, o.interval_end}] = {steady_ns(Clock::now()), -1};
        }
        if (odometry.write(sarloc::dds::to_idl(o))) crew_published.fetch_add(1);
        if (step.reckoning) {
          auto own = *step.reckoning;
          own.stamp += t0;
          reckonings->write(sarloc::dds::to_idl(own));
        }
      }
    });
  }
  app::ProgressBar bar(std::string(to_string(target)) + " " + std::to_string(n) + " rescuers @ " +
                           std::to_string(rate_hz).substr(0, 4) + " Hz",
                       epochs * n);
  std::vector<double> lags_ms;
  std::optional<sarloc::dds::ProcessStats> bench_cpu;  // from the measured phase's start
  // Every rescuer on its own phase; walk straight on (the guidance is not the point here).
  for (std::size_t k = 0; k < epochs && !app::shutdown_requested(); ++k) {
    if (k == warmup_epochs) bench_cpu.emplace();
    for (std::size_t i = 0; i < n; ++i) {
      const auto due = start + k * period + (period * static_cast<long>(i)) / static_cast<long>(n);
      std::this_thread::sleep_until(due);
      if (k >= warmup_epochs) lags_ms.push_back(1e-6 * static_cast<double>(steady_ns(Clock::now()) - steady_ns(due)));
      // Integer stamps: one step's end is exactly the next one's start.
      const auto stamp_of = [&](std::size_t epoch) {
        return t0 + static_cast<TimestampNs>(epoch) * period_ns +
               period_ns * static_cast<TimestampNs>(i) / static_cast<TimestampNs>(n);
      };
      const TimestampNs stamp = stamp_of(k);
      auto& sim = sims[i];
      if (k > 0) {
        double bearing = 0.0;  // east
        if (setup.circle) {  // tangent to the circle around the debris: counter-clockwise
          const Vec3 d = sim.pose().position - centre;
          bearing = std::atan2(d.y(), d.x()) + sarloc::kPi / 2.0;
        }
        if (odometry.write(sarloc::dds::to_idl(sim.walk(bearing, 1.0 / rate_hz, stamp_of(k - 1), stamp)))) {
          ++result.published;
        }
      }
      for (const auto& m : sim.measure(stamp)) {
        const auto sample = sarloc::dds::to_idl(m);
        if (k < warmup_epochs) {  // load only, not measured
          if (measurements.write(sample)) ++result.published;
          continue;
        }
        const std::tuple<std::string, std::uint32_t, std::uint64_t> key{m.rescuer_id, m.signal_id, m.sequence};
        {
          std::lock_guard<std::mutex> lock(mutex);
          samples[key].published = steady_ns(Clock::now());
        }
        if (measurements.write(sample)) ++result.published;
        const std::int64_t returned = steady_ns(Clock::now());
        {
          std::lock_guard<std::mutex> lock(mutex);
          samples[key].write_returned = returned;
        }
        ++result.measurements;
      }
      bar.tick();
    }
  }
  bar.finish();
  if (crew_thread.joinable()) crew_thread.join();
  result.published += crew_published.load();
  if (bench_cpu) result.bench_cpu_percent = bench_cpu->cpu_percent();
  if (!lags_ms.empty()) {
    result.lag_p99_ms = sarloc::percentile(lags_ms, 0.99);
    result.lag_max_ms = sarloc::percentile(lags_ms, 1.0);
  }
  if (intruder) result.intruder_sent = intruder->join();
  std::this_thread::sleep_for(std::chrono::seconds(1));  // stragglers
  std::lock_guard<std::mutex> lock(mutex);
  const double span = measure_to_s - measure_from_s;
  result.rss_early_mb = median_between(rss_series, measure_from_s + 0.2 * span, measure_from_s + 0.3 * span);
  result.rss_end_mb = median_between(rss_series, measure_to_s - 0.1 * span, measure_to_s + 1.0);
  result.rss_growth_mb_per_min = 60.0 * slope_after(rss_series, measure_from_s + 0.5 * span);
  result.refused = refused;
  result.accepted = accepted;
  std::vector<double> latencies;
  std::vector<double> to_write;
  std::vector<double> back;
  for (const auto& [key, t] : samples) {
    if (t.answered < 0) continue;
    latencies.push_back(1e-6 * static_cast<double>(t.answered - t.published));
    to_write.push_back(1e-6 * static_cast<double>(t.answer_written - t.published));
    back.push_back(1e-6 * static_cast<double>(t.answered - t.answer_written));
  }
  result.answered = latencies.size();
  std::vector<double> ff_latencies;
  for (const auto& [key, t] : steps) {
    if (t.second >= 0) ff_latencies.push_back(1e-6 * static_cast<double>(t.second - t.first));
  }
  result.ff_steps = steps.size();
  result.ff_answered = ff_latencies.size();
  if (!ff_latencies.empty()) {
    result.ff_p50_ms = sarloc::percentile(ff_latencies, 0.5);
    result.ff_p99_ms = sarloc::percentile(ff_latencies, 0.99);
    result.ff_max_ms = sarloc::percentile(ff_latencies, 1.0);
  }
  if (!latencies.empty()) {  // otherwise -1: no answer at all
    result.p50_ms = sarloc::percentile(latencies, 0.5);
    result.p99_ms = sarloc::percentile(latencies, 0.99);
    result.max_ms = sarloc::percentile(latencies, 1.0);
    result.to_write_p50_ms = sarloc::percentile(to_write, 0.5);
    result.return_p50_ms = sarloc::percentile(back, 0.5);
  }
  if (cpu.size() > 2) {
    // The first status covers start-up; the mean of the rest is the load's.
    double sum = 0.0;
    for (std::size_t i = 1; i < cpu.size(); ++i) sum += cpu[i];
    result.cpu_percent = sum / static_cast<double>(cpu.size() - 1);
  }
  result.rss_mb = rss;
  if (!setup.trace_dir.empty()) write_trace(setup.trace_dir + "/" + run_name + ".csv", samples);
  responder->stop(std::chrono::seconds(5));
  return result;
}

nlohmann::json to_json(const LoadResult& r) {
  return {{"target", to_string(r.target)},
          {"repeat", r.repeat},
          {"rescuers", r.rescuers},
          {"rate_hz", r.rate_hz},
          {"measurements", r.measurements},
          {"answered", r.answered},
          {"p50_ms", r.p50_ms},
          {"p99_ms", r.p99_ms},
          {"max_ms", r.max_ms},
          {"to_write_p50_ms", r.to_write_p50_ms},
          {"return_p50_ms", r.return_p50_ms},
          {"cpu_percent", r.cpu_percent},
          {"rss_mb", r.rss_mb},
          {"rss_early_mb", r.rss_early_mb},
          {"rss_end_mb", r.rss_end_mb},
          {"rss_growth_mb_per_min", r.rss_growth_mb_per_min},
          {"refused", r.refused},
          {"accepted", r.accepted},
          {"published", r.published},
          {"intruder_sent", r.intruder_sent},
          {"lag_p99_ms", r.lag_p99_ms},
          {"lag_max_ms", r.lag_max_ms},
          {"bench_cpu_percent", r.bench_cpu_percent},
          {"firefighters", r.firefighters},
          {"ff_steps", r.ff_steps},
          {"ff_answered", r.ff_answered},
          {"ff_p50_ms", r.ff_p50_ms},
          {"ff_p99_ms", r.ff_p99_ms},
          {"ff_max_ms", r.ff_max_ms}};
}

void print_run_header() {
  std::printf("%-7s %3s %9s %8s %10s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s\n", "target", "run",
              "rescuers", "rate Hz", "measured", "answered", "p50 ms", "p99 ms", "max ms", "write ms", "back ms",
              "cpu %", "rss MB", "rss@25%", "rss end", "MB/min", "refused", "intruder", "lag99 ms", "bench %");
}

void print_run_row(const LoadResult& r) {
  std::printf(
      "%-7s %3zu %9zu %8.1f %10zu %9zu %9.2f %9.2f %9.2f %9.2f %9.2f %9.0f %9.1f %9.1f %9.1f %9.2f %9llu %9zu %9.1f "
      "%9.0f\n",
      to_string(r.target), r.repeat, r.rescuers, r.rate_hz, r.measurements, r.answered, r.p50_ms, r.p99_ms, r.max_ms,
      r.to_write_p50_ms, r.return_p50_ms, r.cpu_percent, r.rss_mb, r.rss_early_mb, r.rss_end_mb,
      r.rss_growth_mb_per_min, static_cast<unsigned long long>(r.refused), r.intruder_sent, r.lag_p99_ms,
      r.bench_cpu_percent);
  if (r.firefighters > 0) {
    std::printf(
        "        and %zu firefighters: %zu steps measured, %zu answered, step -> position p50 %.2f ms, p99 %.2f ms, "
        "max %.2f ms\n",
        r.firefighters, r.ff_steps, r.ff_answered, r.ff_p50_ms, r.ff_p99_ms, r.ff_max_ms);
  }
  std::fflush(stdout);
}

/// Medians over the repeats of one target at one load point.
struct Medians {
  std::size_t runs = 0;
  std::size_t measurements = 0;  ///< summed over the runs
  std::size_t answered = 0;
  double p50_ms = -1.0;
  double p99_ms = -1.0;
  double max_ms = -1.0;
  double cpu_percent = -1.0;
  double rss_mb = -1.0;
};

Medians medians_of(const std::vector<LoadResult>& runs, Target target, std::size_t rescuers) {
  Medians m;
  std::vector<double> p50, p99, max, cpu, rss;
  for (const auto& r : runs) {
    if (r.target != target || r.rescuers != rescuers) continue;
    ++m.runs;
    m.measurements += r.measurements;
    m.answered += r.answered;
    // A run with no answer at all counts as infinitely slow, not as missing.
    const double inf = std::numeric_limits<double>::infinity();
    p50.push_back(r.p50_ms >= 0.0 ? r.p50_ms : inf);
    p99.push_back(r.p99_ms >= 0.0 ? r.p99_ms : inf);
    max.push_back(r.max_ms >= 0.0 ? r.max_ms : inf);
    if (r.cpu_percent >= 0.0) cpu.push_back(r.cpu_percent);
    if (r.rss_mb >= 0.0) rss.push_back(r.rss_mb);
  }
  if (m.runs == 0) return m;
  m.p50_ms = sarloc::percentile(p50, 0.5);
  m.p99_ms = sarloc::percentile(p99, 0.5);
  m.max_ms = sarloc::percentile(max, 0.5);
  if (!cpu.empty()) m.cpu_percent = sarloc::percentile(cpu, 0.5);
  if (!rss.empty()) m.rss_mb = sarloc::percentile(rss, 0.5);
  return m;
}

nlohmann::json to_json(const Medians& m) {
  return {{"runs", m.runs},           {"measurements", m.measurements}, {"answered", m.answered},
          {"p50_ms", m.p50_ms},       {"p99_ms", m.p99_ms},             {"max_ms", m.max_ms},
          {"cpu_percent", m.cpu_percent}, {"rss_mb", m.rss_mb}};
}

double ratio(double a, double b) { return a >= 0.0 && b > 0.0 ? a / b : -1.0; }

/// Side by side: echo and sarloc medians over the repeats, and sarloc/echo for p50 and p99.
nlohmann::json print_summary(const std::vector<LoadResult>& runs, const std::vector<std::size_t>& loads, double rate_hz,
                             std::size_t repeats) {
  std::printf("\nmedians over %zu run(s) per target, %.1f Hz:\n", repeats, rate_hz);
  std::printf("%9s | %8s %8s %8s %6s | %8s %8s %8s %6s %7s | %9s %9s\n", "rescuers", "echo p50", "p99", "max", "cpu %",
              "sarloc p50", "p99", "max", "cpu %", "rss MB", "p50 ratio", "p99 ratio");
  nlohmann::json out = nlohmann::json::array();
  for (const auto n : loads) {
    const Medians echo = medians_of(runs, Target::kEcho, n);
    const Medians core = medians_of(runs, Target::kSarloc, n);
    std::printf("%9zu | %8.2f %8.2f %8.2f %6.0f | %10.2f %8.2f %8.2f %6.0f %7.1f | %9.2f %9.2f\n", n, echo.p50_ms,
                echo.p99_ms, echo.max_ms, echo.cpu_percent, core.p50_ms, core.p99_ms, core.max_ms, core.cpu_percent,
                core.rss_mb, ratio(core.p50_ms, echo.p50_ms), ratio(core.p99_ms, echo.p99_ms));
    out.push_back({{"rescuers", n},
                   {"rate_hz", rate_hz},
                   {"echo", to_json(echo)},
                   {"sarloc", to_json(core)},
                   {"ratio_p50", ratio(core.p50_ms, echo.p50_ms)},
                   {"ratio_p99", ratio(core.p99_ms, echo.p99_ms)}});
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-bench-latency: measurement -> estimate latency of sarloc-core under load, against a DDS echo"};
  std::string config_path = app::shipped_mission("default.yaml");
  std::vector<std::size_t> loads{1, 10, 50};
  std::vector<std::string> target_names{"echo", "sarloc"};
  std::string echo_handoff = "listener";
  std::size_t repeats = 1;
  double rate = 1.0;
  double duration = 30.0;
  std::size_t search_rescuers = 50;
  std::vector<double> search_rates{1, 2, 4, 6, 8, 12, 16};
  double p99_limit_ms = 100.0;
  bool search = true;
  int domain = 60;
  std::string json_path;
  std::string log_level = "warn";
  BenchSetup setup;
  cli.add_option("-c,--config", config_path,
                 std::string("mission YAML (victims, sensors, filter parameters; default: default.yaml in ") +
                     app::kShippedMissionsHelp + ")");
  cli.add_option("--rescuers", loads, "load points: numbers of simulated rescuers (e.g. 1,10,50)")
      ->delimiter(',')
      ->capture_default_str();
  cli.add_option("--targets", target_names, "responders, in the order run at each load point: echo, sarloc")
      ->delimiter(',')
      ->capture_default_str();
  cli.add_option("--echo-handoff", echo_handoff,
                 "listener: the echo answers on the DDS listener thread; queue: through a worker, as sarloc-core; waitset: a worker in a DDS WaitSet")
      ->capture_default_str();
  cli.add_option("--repeat", repeats, "runs of every (load point, target), interleaved; the summary takes medians")
      ->capture_default_str();
  cli.add_option("--rate", rate, "measurement rate of the load points (Hz)")->capture_default_str();
  cli.add_option("--duration", duration, "seconds per load point")->capture_default_str();
  cli.add_option("--warmup", setup.warmup_s,
                 "seconds of load before measuring (filters start at ~1700 components and prune over tens of "
                 "epochs; 0 measures that opening phase)")
      ->capture_default_str();
  cli.add_option("--admission", setup.admission,
                 "core.admission of the responder's mission copy: roster (only the bench's rescuers) or open")
      ->capture_default_str();
  cli.add_option("--intruder-ids", setup.intruder_ids,
                 "a hostile publisher cycles through this many rescuer ids no one serves (0: none)")
      ->capture_default_str();
  cli.add_option("--intruder-rate", setup.intruder_rate, "the hostile publisher's samples per second")
      ->capture_default_str();
  cli.add_flag("!--intruder-field-only", setup.intruder_odometry, "the hostile publisher sends no odometry");
  cli.add_flag("--circle", setup.circle,
               "rescuers circle the debris (stay in range for soaks) instead of walking straight on (east)");
  cli.add_option("--search-rescuers", search_rescuers, "rescuers for the highest-rate search (sarloc-core only)")
      ->capture_default_str();
  cli.add_option("--search-rates", search_rates, "rates tried, increasing, until p99 exceeds the limit (e.g. 1,2,4)")
      ->delimiter(',')
      ->capture_default_str();
  cli.add_option("--p99-limit-ms", p99_limit_ms, "the p99 bound of the rate search")->capture_default_str();
  cli.add_flag("!--no-search", search, "skip the highest-rate search");
  cli.add_option("--domain", domain, "DDS domain id")->capture_default_str();
  cli.add_option("--seed", setup.seed, "seed of the rescuers' placement and noise")->capture_default_str();
  cli.add_option("--json", json_path, "write the figures as JSON here");
  cli.add_option("--trace-dir", setup.trace_dir,
                 "write every run's per-measurement times here (CSV, steady-clock ns: published, write returned, "
                 "answer written, answer received, answered)");
  std::size_t firefighters = 0;
  cli.add_option("--firefighters", firefighters,
                 "firefighters searching the mission's building in every sarloc-core run, about 2 steps a second "
                 "each (the mission needs a building: section)")
      ->capture_default_str();
  std::string receiver = "mission";
  cli.add_option("--receiver", receiver,
                 "the simulated devices' receiver: mission (the mission file's), ideal or realistic. The realistic "
                 "one separates every device's pulses in this process and falls behind schedule at hundreds of "
                 "rescuers on 2 cores")
      ->capture_default_str();
  cli.add_option("--core-exe", setup.core_exe,
                 "daemon executable to measure instead of sarloc-core next to this one (e.g. another build)");
  app::add_log_level_option(cli, log_level);
  cli.set_version_flag("--version", SARLOC_VERSION);
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-bench-latency", [&] {
    app::setup_logging(log_level, "bench");
    if (!(rate > 0.0 && rate <= 100.0)) throw ConfigError("--rate = " + config_value(rate) + ": must be in (0, 100]");
    if (!(duration >= 2.0)) throw ConfigError("--duration = " + config_value(duration) + ": must be >= 2 s");
    if (!(setup.warmup_s >= 0.0 && setup.warmup_s <= 3600.0)) {
      throw ConfigError("--warmup = " + config_value(setup.warmup_s) + ": must be in [0, 3600]");
    }
    if (repeats < 1) throw ConfigError("--repeat = 0: must be >= 1");
    if (setup.admission != "roster" && setup.admission != "open") {
      throw ConfigError("--admission = '" + setup.admission + "': must be roster or open");
    }
    if (!(setup.intruder_rate > 0.0 && setup.intruder_rate <= 100000.0)) {
      throw ConfigError("--intruder-rate = " + config_value(setup.intruder_rate) + ": must be in (0, 100000]");
    }
    if (domain < 0 || domain > 232) throw ConfigError("--domain = " + config_value(domain) + ": must be in [0, 232]");
    std::vector<Target> targets;
    for (const auto& t : target_names) targets.push_back(parse_target(t));
    if (receiver != "mission" && receiver != "ideal" && receiver != "realistic") {
      throw ConfigError("--receiver = '" + receiver + "': must be mission, ideal or realistic");
    }
    if (receiver != "mission") setup.receiver = avalanche::parse_receiver_kind(receiver, "--receiver");
    setup.echo_handoff = bench::parse_echo_handoff(echo_handoff);
    setup.mission = app::load_mission_config(config_path);
    setup.bin_dir = fs::canonical("/proc/self/exe").parent_path().string();
    setup.log_dir = (fs::temp_directory_path() / ("sarloc-bench-" + std::to_string(getpid()))).string();
    fs::create_directories(setup.log_dir);
    if (!setup.trace_dir.empty()) fs::create_directories(setup.trace_dir);
    setup.config_path = fs::absolute(config_path).string();
    if (setup.core_exe.empty()) setup.core_exe = setup.bin_dir + "/sarloc-core";
    if (!fs::is_regular_file(setup.core_exe)) throw ConfigError("--core-exe = '" + setup.core_exe + "': no such file");
    setup.core_exe = fs::absolute(setup.core_exe).string();
    setup.domain = static_cast<std::uint32_t>(domain);
    if (firefighters > 0) {
      if (firefighters > 400)
        throw ConfigError("--firefighters = " + std::to_string(firefighters) + ": must be at most 400");
      const double search_s = std::max(30.0, setup.warmup_s + duration + 5.0);  // 30 s: the shortest search
      spdlog::warn("walking {} firefighters' searches ({:.0f} s each) before the first run", firefighters, search_s);
      setup.crew = std::make_shared<const bench::FirefighterCrew>(setup.mission, firefighters, search_s, setup.seed);
    }

    nlohmann::json out;
    out["seed"] = setup.seed;
    out["warmup_s"] = setup.warmup_s;
    out["duration_s"] = duration;
    out["echo_handoff"] = bench::to_string(setup.echo_handoff);
    out["admission"] = setup.admission;
    out["circle"] = setup.circle;
    out["intruder_ids"] = setup.intruder_ids;
    out["intruder_rate"] = setup.intruder_rate;
    out["receiver"] = receiver;
    out["firefighters"] = firefighters;
    out["runs"] = nlohmann::json::array();
    std::vector<LoadResult> runs;
    print_run_header();
    // Interleaved: every target at every load point once, then again, so that a noisy
    // neighbour on the machine hits all variants alike.
    for (std::size_t rep = 0; rep < repeats; ++rep) {
      for (const auto n : loads) {
        for (const auto target : targets) {
          runs.push_back(run_load(setup, target, rep, n, rate, duration));
          print_run_row(runs.back());
          out["runs"].push_back(to_json(runs.back()));
          if (app::shutdown_requested()) return app::ExitCode::kInterrupted;
        }
      }
    }
    out["loads"] = print_summary(runs, loads, rate, repeats);
    if (search) {
      std::printf("\nhighest rate with %zu rescuers and p99 < %.0f ms (sarloc-core):\n", search_rescuers, p99_limit_ms);
      print_run_header();
      double best = 0.0;
      out["rate_search"] = nlohmann::json::array();
      for (const double r_hz : search_rates) {
        const auto r = run_load(setup, Target::kSarloc, 0, search_rescuers, r_hz, std::max(10.0, duration / 2.0));
        print_run_row(r);
        out["rate_search"].push_back(to_json(r));
        const bool ok = r.p99_ms >= 0.0 && r.p99_ms < p99_limit_ms && r.answered * 100 >= r.measurements * 99;
        if (!ok || app::shutdown_requested()) break;
        best = r_hz;
      }
      std::printf("=> %.1f Hz\n", best);
      out["highest_rate_hz"] = best;
    }
    if (!json_path.empty()) app::write_json_file(json_path, out);
    return app::ExitCode::kOk;
  });
}
