// sarloc-rescuer: the app on a responder's device. An avalanche rescuer's publishes field
// measurements, odometry and its position, shows the rescuer what to do, and keeps guiding on
// the device when the core daemon is unreachable (dds/rescuer_node.hpp). A firefighter's runs
// the boot INS, publishes odometry and alarms, and dead reckons when the daemon is silent
// (firefighter_device_loop.hpp).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <thread>

#include "firefighter_device_loop.hpp"
#include "sarloc/app/command_line.hpp"
#include "sarloc/app/imu_source_yaml.hpp"
#include "sarloc/app/json_io.hpp"
#include "sarloc/app/logging.hpp"
#include "sarloc/app/node_options.hpp"
#include "sarloc/app/run_main.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/avalanche/found_victim.hpp"
#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/common/statistics.hpp"
#include "sarloc/core/common/time_units.hpp"
#include "sensor_source.hpp"
#include "simulated_digs.hpp"

namespace {

using namespace sarloc;

const char* mode_name(responder::GuidanceMode mode) {
  switch (mode) {
    case responder::GuidanceMode::kOpening: return "COARSE SEARCH";
    case responder::GuidanceMode::kApproach: return "APPROACH";
    case responder::GuidanceMode::kFineSearch: return "FINE SEARCH";
    case responder::GuidanceMode::kFound: return "FOUND - PROBE HERE";
    case responder::GuidanceMode::kPrimarySearch:
      return "PRIMARY SEARCH";
  }
  return "?";
}

const char* display_status(responder::EstimatorStatus status) {
  switch (status) {
    case responder::EstimatorStatus::kInitialising: return "init";
    case responder::EstimatorStatus::kMultimodal: return "multimodal";
    case responder::EstimatorStatus::kConverged: return "converged";
    case responder::EstimatorStatus::kLocated: return "located";
    case responder::EstimatorStatus::kFound: return "FOUND";
  }
  return "?";
}

// What the rescuer reads on the device: direction, distance, mode, victims.
std::string display_line(const std::string& id, const sarloc::dds::EpochResult& r) {
  std::string line = id + " | ";
  if (!r.guidance) {
    line += "no signal: walk straight ahead (primary search)";
  } else if (r.guidance->mode == responder::GuidanceMode::kPrimarySearch) {
    const auto& g = *r.guidance;
    const double deg = g.bearing_rad * 180.0 / sarloc::kPi;
    char buf[160];
    std::snprintf(buf, sizeof(buf), "no signal: search plan's strip | turn %3.0f deg %-5s | next point %.0f m ahead",
                  std::fabs(deg), deg >= 0 ? "left" : "right", g.distance_m);
    line += buf;
  } else {
    const auto& g = *r.guidance;
    const double deg = g.bearing_rad * 180.0 / sarloc::kPi;
    char buf[200];
    std::snprintf(buf, sizeof(buf), "signal %u | %-18s | turn %3.0f deg %-5s | walk %.1f m | dist %.1f m +- %.1f m",
                  g.signal_id, mode_name(g.mode), std::fabs(deg), deg >= 0 ? "left" : "right", g.step_m,
                  g.distance_m, g.uncertainty_radius_m);
    line += buf;
  }
  line += " | victims:";
  for (const auto& [signal, status] : r.signals) line += " " + std::to_string(signal) + "=" + display_status(status);
  for (const auto signal : r.conflicting_signals) line += " | signal " + std::to_string(signal) + ": CONFLICTING ESTIMATES";
  line += std::string(" | guidance: ") + responder::to_string(r.source);
  if (!r.daemon_reachable) line += " (core daemon unreachable)";
  return line;
}


}  // namespace

int main(int argc, char** argv) {
  app::install_shutdown_handlers();
  CLI::App cli{"sarloc-rescuer: the rescuer's device app (simulated or recorded sensors)"};
  app::NodeOptions options;
  std::string rescuer_id;
  std::string source = "sim";
  std::string summary_path;
  bool quiet = false;
  app::add_node_options(cli, options);
  cli.add_option("--id", rescuer_id, "this rescuer's id (one of the mission's rescuers)")->required();
  cli.add_option("--source", source,
                 "'sim' (mission simulator) or a recorded file: JSON-lines sensor file (avalanche rescuer), "
                 "boot IMU CSV (firefighter)");
  std::string imu_source;
  cli.add_option("--imu-source", imu_source,
                 "a firefighter's recorded boot IMU file is in this IMU source's format (config/imu/*.yaml; "
                 "default: the sarloc boot IMU CSV)")
      ->check(CLI::ExistingFile);
  cli.add_option("--summary", summary_path, "write a JSON summary here on exit");
  std::string sim_world;
  cli.add_option("--sim-world", sim_world,
                 "simulated avalanche missions: the file through which the mission's simulated devices share "
                 "the transmitters their digs switched off (sarloc-mission gives one per run; without it a "
                 "device silences a dug-out transmitter when the picture says so)");
  cli.add_flag("--quiet", quiet, "do not print the guidance line every epoch");
  if (auto code = app::parse_command_line(cli, argc, argv)) return *code;

  return app::run_main("sarloc-rescuer", [&] {
    app::setup_logging(options.log_level, rescuer_id);
    const auto mission = app::load_mission_config(options.config_path);
    if (const auto* firefighter = mission.firefighter(rescuer_id)) {
      // A recording the mission names plays unless the command line names another source.
      const bool from_mission = source == "sim" && !firefighter->recording.empty();
      const std::string boot = from_mission ? firefighter->recording : source;
      const std::string format_path = !imu_source.empty() ? imu_source : from_mission ? firefighter->imu_source : "";
      const auto format = format_path.empty() ? firefighter::sarloc_csv() : app::load_imu_source(format_path);
      return rescuer::run_firefighter_device(mission, *firefighter, options, boot, format, summary_path, quiet);
    }
    const auto node_config = mission.rescuer_config(rescuer_id);  // throws ConfigError for an unknown id
    const sarloc::dds::MissionClock clock = options.clock(mission);
    const TimestampNs epoch = clock.epoch();

    std::unique_ptr<rescuer::SensorSource> sensors;
    if (source == "sim") {
      sensors = std::make_unique<rescuer::SimulatedSource>(mission.scenario, rescuer_id,
                                                           mission.estimators.avalanche_rescuer.search.step_length_m,
                                                           mission.command.incident.origin);
    } else {
      sensors = std::make_unique<rescuer::RecordedSource>(source, rescuer_id, node_config.team,
                                                          mission.command.incident.origin);
    }

    auto participant =
        std::make_shared<sarloc::dds::Participant>(options.participant(mission, "rescuer-" + rescuer_id, rescuer_id));
    sarloc::dds::RescuerNode node(participant, node_config, clock);
    // The device's separation asks its own filters when carrier and timing cannot decide, once
    // they have moved with the step just walked.
    sensors->set_consistency(
        [&node](std::uint32_t signal, const Vec3& field, const Vec3& noise, std::uint8_t axes) {
          return node.local_estimator().field_fit(signal, field, noise, axes);
        },
        [&node](const responder::Odometry& o) { node.move({o}); });

    // The first samples are worth delivering: give discovery a moment to match the daemon.
    if (!node.wait_for_daemon(std::chrono::seconds(5))) {
      spdlog::warn("no core daemon matched within 5 s: starting anyway (guidance on the device until one answers)");
    }
    std::optional<responder::Guidance> followed;
    std::vector<double> latencies;
    std::map<std::string, std::size_t> guided_by;  // epochs per guidance source
    std::size_t daemon_after_fallback = 0;          // daemon-guided epochs after the first fallback
    std::map<std::uint32_t, double> error_when_found;  // simulation truth: the diggers' error
    std::map<std::uint32_t, double> radius_when_found;  // the 95 % radius the device stated then
    std::map<std::uint32_t, std::size_t> victim_when_found;  // the victim that FOUND named (found_victim.hpp)
    // Every signal heard, with the furthest status it reached: a victim found and then left
    // behind (out of range) is still one this device found.
    std::map<std::uint32_t, responder::EstimatorStatus> furthest;
    rescuer::SimulatedDigs digs;
    digs.world = rescuer::SimulatedWorld(sim_world);
    std::size_t epochs = 0;
    const auto period_ns = seconds_to_ns(mission.period_s);
    sarloc::dds::EpochResult last;
    std::optional<responder::ResponderPosition> last_fix;
    std::string sector = mission.sector_of.count(rescuer_id) != 0 ? mission.sector_of.at(rescuer_id) : "";
    for (std::size_t k = 0; !app::shutdown_requested(); ++k) {
      const TimestampNs stamp = epoch + static_cast<TimestampNs>(k) * period_ns;
      // Wait for this epoch's moment on the (possibly accelerated) mission clock.
      while (!app::shutdown_requested() && clock.now() < stamp) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      if (app::shutdown_requested()) break;
      auto samples = sensors->next(stamp, followed);
      if (!samples) {
        spdlog::info("sensor source exhausted after {} epochs", epochs);
        break;
      }
      // The device's separation: a new, reacquired or separated signal is worth a line.
      for (const auto& sample : samples->samples) {
        const auto* m = std::get_if<avalanche::FieldMeasurement>(&sample);
        if (m != nullptr && m->event != avalanche::SignalEvent::kNone)
          spdlog::info("signal {}: {} ({} pulses unattributed in this window)", m->signal_id, to_string(m->event),
                       m->unattributed_pulses);
      }
      last = node.epoch(samples->odometry, samples->position, samples->samples);
      if (samples->position) last_fix = samples->position;
      if (samples->position && !mission.sector_areas.empty()) {
        // Walked into another sector's area: its daemon serves this device from now on, and
        // takes the search over from this one's (docs/architecture.md, "Hand-over between sectors").
        const std::string next =
            mission.sector_areas.sector_for(sector, samples->position->position.position.head<2>());
        if (next != sector) {
          spdlog::info("walked into sector '{}' (from '{}'): its core daemon serves this device now", next, sector);
          node.move_to(app::MissionConfig::partitions_of_sector(next));
          sector = next;
        }
      }
      ++epochs;
      if (last.latency_ms >= 0.0) latencies.push_back(last.latency_ms);
      followed = last.guidance;
      ++guided_by[responder::to_string(last.source)];
      if (node.fallbacks() > 0 && last.source == responder::GuidanceSource::kDaemon) ++daemon_after_fallback;
      // The diggers' error is the one when the rescuer stood over the victim, not later.
      for (const auto& [signal, status] : last.signals) {
        auto& best = furthest.emplace(signal, status).first->second;
        best = std::max(best, status);
        if (status != responder::EstimatorStatus::kFound || error_when_found.count(signal) != 0) continue;
        const auto estimate = node.local_estimator().estimate_of(signal);
        const std::vector<Vec3> victims = sensors->true_victims_relative();
        if (!estimate || victims.empty()) continue;
        const Vec3& where = estimate->relative.position;
        const auto own = sensors->victim_of_signal(signal);
        // Near no victim (a false FOUND): scored against the victim the signal followed, else the nearest.
        auto victim = avalanche::victim_of_found(where, avalanche::found_reach(estimate->relative.covariance), victims, own);
        if (!victim) victim = avalanche::victim_of_found(where, std::numeric_limits<double>::infinity(), victims, own);
        victim_when_found[signal] = *victim;
        error_when_found[signal] = (where - victims[*victim]).norm();
        radius_when_found[signal] = radius95_3d(estimate->relative.covariance);
      }
      if (source == "sim") rescuer::simulate_digs(node, *sensors, mission.scenario, last, stamp, digs);
      if (!quiet) spdlog::info("{}", display_line(rescuer_id, last));
    }

    if (!summary_path.empty()) {
      mission::DeviceSummary d;
      d.rescuer_id = rescuer_id;
      d.epochs = epochs;
      d.distance_walked_m = sensors->distance_walked_m();
      d.fallbacks = node.fallbacks();
      d.guidance_switches = node.guidance_switches();
      d.guided_by = guided_by;
      d.daemon_after_fallback = daemon_after_fallback;
      d.latency_samples = latencies.size();
      if (!latencies.empty()) {  // no daemon answer at all: no percentiles (the mission shows -1)
        d.latency_p50_ms = sarloc::percentile(latencies, 0.5);
        d.latency_p99_ms = sarloc::percentile(latencies, 0.99);
      }
      for (const auto& [signal, status] : furthest) {
        const auto named = victim_when_found.find(signal);
        mission::DeviceSignal s{signal, status,
                                named != victim_when_found.end() ? std::optional<std::size_t>(named->second)
                                                                 : sensors->victim_of_signal(signal),
                                std::nullopt, std::nullopt};
        // The diggers' view: this device's own estimate against the truth when it was found.
        if (const auto it = error_when_found.find(signal); it != error_when_found.end()) s.relative_error_m = it->second;
        if (const auto it = radius_when_found.find(signal); it != radius_when_found.end()) s.radius95_m = it->second;
        d.signals.push_back(s);
      }
      if (const auto antenna = sensors->true_antenna(); antenna && last_fix) {
        d.gnss_error_m = (last_fix->position.position - *antenna).head<2>().norm();
      }
      app::write_json_file(summary_path, app::to_json(d));
    }
    // Ended in order (SIGTERM or the end of the source): say so, so that it is no lost link.
    node.sign_off(std::chrono::seconds(2));
    return app::ExitCode::kOk;
  });
}
