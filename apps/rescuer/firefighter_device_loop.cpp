#include "firefighter_device_loop.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <thread>

#include "sarloc/core/common/time_units.hpp"
#include "sarloc/app/exit_codes.hpp"
#include "sarloc/app/json_io.hpp"
#include "sarloc/app/shutdown_signal.hpp"
#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/seeds.hpp"
#include "sarloc/core/estimator/firefighter_device.hpp"
#include "sarloc/core/mission/firefighter_summary.hpp"
#include "sarloc/core/mission/simulated_firefighter.hpp"
#include "sarloc/dds/firefighter_node.hpp"
#include "imu_file.hpp"

namespace sarloc::rescuer {
namespace {

std::uint64_t seed_of_name(std::uint64_t seed, const std::string& name) {
  return derive_seed(seed, std::hash<std::string>{}(name) & 0xFFFFFFFFULL);
}

const char* source_name(responder::PositionSource s) {
  switch (s) {
    case responder::PositionSource::kGnss: return "GNSS";
    case responder::PositionSource::kMapAided: return "map-aided";
    case responder::PositionSource::kDeadReckoning: return "DEAD RECKONING";
    case responder::PositionSource::kManual: return "manual";
  }
  return "?";
}

}  // namespace

app::ExitCode run_firefighter_device(const app::MissionConfig& mission, const app::FirefighterEntry& ff,
                                     const app::NodeOptions& options, const std::string& source,
                                     const firefighter::ImuSourceFormat& format, const std::string& summary_path,
                                     bool quiet) {
  const auto& placement = mission.estimators.firefighter;
  if (!mission.world || !placement.building) {
    throw ConfigError("rescuers[" + ff.id + "].role = firefighter: the mission has no building: section");
  }
  const dds::MissionClock clock = options.clock(mission);
  const TimestampNs epoch = clock.epoch();
  const auto mission_s = [&](TimestampNs stamp) { return 1e-9 * static_cast<double>(stamp - epoch); };
  // The boot's samples: the simulated search (with its truth, for the summary) or a recording.
  std::optional<mission::SimulatedFirefighter> sim;
  std::optional<ImuFile> file;
  if (source == "sim") {
    sim.emplace(*mission.world, ff.spec, seed_of_name(mission.scenario.seed, ff.team), seed_of_name(mission.scenario.seed, ff.id));
  } else {
    file.emplace(source, format);  // ConfigError naming the file for a missing one or a wrong header
  }
  const auto next_sample = [&]() -> std::optional<firefighter::ImuSample> {
    return sim ? sim->next_sample() : file->next();
  };
  estimator::FirefighterDeviceConfig device_config;
  if (file) {  // the recording's sensor: its rate and its stance detector (config/imu/)
    if (format.rate_hz > 0.0) device_config.ins.rate_hz = format.rate_hz;
    firefighter::apply_declared(format, device_config.ins);
  }
  estimator::FirefighterDevice device(ff.id, ff.team, device_config, epoch);
  auto participant = std::make_shared<dds::Participant>(options.participant(mission, "rescuer-" + ff.id, ff.id));
  dds::FirefighterNodeConfig node_config;
  node_config.responder_id = ff.id;
  node_config.team = ff.team;
  node_config.partitions = mission.rescuer_config(ff.id).partitions;
  node_config.daemon_timeout_s = mission.rescuer.fallback_timeout_s;
  dds::FirefighterNode node(participant, node_config, clock);
  if (!node.wait_for_daemon(std::chrono::seconds(5))) {
    spdlog::warn("no core daemon matched within 5 s: starting anyway (dead reckoning on the device until one answers)");
  }
  // Dead reckoning starts from the reported entry (where the crew aligns, turned to its wall).
  if (auto entry = estimator::entry_fix(*mission.world, placement, ff.id, ff.team, ff.spec.entry, ff.spec.hand)) {
    device.start_at(*entry);
  }
  const auto truth_incident = [&](double t) {
    const auto truth = sim->truth(t);
    return std::make_pair(placement.to_incident(truth.position), static_cast<std::int32_t>(truth.floor));
  };
  mission::FirefighterScore score(ff.id, ff.team, ff.spec.enter_at_s);
  bool mayday_pressed = false, reset_pressed = false;
  bool on_own = false;
  std::optional<responder::ResponderPosition> last_fix;
  std::size_t published = 0;
  while (!app::shutdown_requested()) {
    auto sample = next_sample();
    if (!sample) break;
    // The sample's moment on the (possibly accelerated) mission clock.
    const TimestampNs at = epoch + seconds_to_ns(sample->t);
    while (!app::shutdown_requested() && clock.now() < at) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    try {
      device.push(*sample);
    } catch (const InputError& e) {  // beyond the sensor's range, or not after the last one
      spdlog::warn("{}: IMU sample at t = {:.3f} s skipped: {}", ff.id, sample->t, e.what());
      continue;
    }
    // The firefighter's own hand on the device (simulated: the mission's mayday_at_s, reset_at_s).
    if (!mayday_pressed && ff.spec.mayday_at_s >= 0.0 && sample->t >= ff.spec.mayday_at_s) {
      device.press_mayday();
      mayday_pressed = true;
    }
    if (!reset_pressed && ff.spec.reset_at_s >= 0.0 && sample->t >= ff.spec.reset_at_s) {
      device.reset(responder::AlarmKind::kMayday);
      device.reset(responder::AlarmKind::kMotionless);
      reset_pressed = true;
    }
    const auto odometry = device.take_odometry();
    if (!odometry) continue;
    node.publish_odometry(*odometry);
    ++published;
    for (const auto& a : device.alarm_changes()) {
      node.publish_alarm(a);
      score.on_alarm(a, epoch);
      spdlog::warn("{}: {} alarm {}", ff.id, responder::to_string(a.kind), a.active ? "RAISED" : "cleared");
    }
    for (const auto& fix : node.take_fixes()) {
      const double t = mission_s(fix.stamp);
      if (sim) {
        const auto [truth, floor] = truth_incident(t);
        score.on_fix(t, fix, truth, floor);
      } else {
        score.on_fix_without_truth(t, fix);
      }
      try {
        device.on_fix(fix);
      } catch (const InputError& e) {
        spdlog::warn("{}: ignoring the daemon's position: {}", ff.id, e.what());
      }
      last_fix = fix;
    }
    const bool silent = node.daemon_silent();
    if (silent != on_own) {
      spdlog::warn("{}: {}", ff.id, silent ? "no position from the core daemon: dead reckoning on the device"
                                           : "the core daemon's map-aided position again");
      on_own = silent;
    }
    if (silent) score.add_dead_reckoning(odometry->interval_end > odometry->interval_start
                                             ? mission_s(odometry->interval_end) - mission_s(odometry->interval_start)
                                             : 0.0);
    // The device's own position once a mission second: its writer is the firefighter's link at
    // incident command, and while the daemon is silent it is the best position there is.
    if (auto own = device.take_own_position()) {
      node.publish_position(*own);
      if (sim) score.on_own_position(*own, truth_incident(mission_s(own->stamp)).first);
    }
    if (!quiet && published % 10 == 0) {
      const auto shown = silent ? device.dead_reckoning() : last_fix;
      if (shown) {
        spdlog::info("{} | {} | ({:.1f}, {:.1f}) floor {} +- {:.1f} m{}{}{}", ff.id, source_name(shown->source),
                     shown->position.position.x(), shown->position.position.y(), shown->floor,
                     std::sqrt(shown->position.covariance.topLeftCorner<2, 2>().trace()),
                     shown->converged ? " | converged" : "", shown->confirmed ? " | confirmed" : "",
                     shown->map_error_suspected ? " | MAP ERROR SUSPECTED" : "");
      }
    }
  }
  spdlog::info("{}: IMU source ended after {} odometry steps{}", ff.id, published,
               file ? " (" + std::to_string(file->skipped_rows()) + " malformed rows skipped)" : std::string());
  if (!summary_path.empty()) {
    // A recording has no truth: its summary holds the alarms and the distance the INS walked.
    const auto s = sim ? score.summary(sim->distance_m(), sim->stop(), device_config.ins.motionless_after_s)
                       : score.summary(device.distance_walked_m(), std::nullopt, device_config.ins.motionless_after_s);
    app::write_json_file(summary_path, app::to_json(s));
  }
  // Ended in order (SIGTERM or the end of the source): say so, so that it is no lost link.
  node.sign_off(std::chrono::seconds(2));
  return app::ExitCode::kOk;
}

}  // namespace sarloc::rescuer
