#pragma once
// The DDS side of a firefighter's device (sarloc-rescuer, role firefighter). It only converts
// and publishes; the device's logic (INS, alarms, dead reckoning) is estimator::FirefighterDevice.
//   - Odometry (2 Hz boot INS) into the sector's partition, for the core daemon;
//   - ResponderAlarm (motionless, mayday) at once, RELIABLE, TRANSIENT_LOCAL;
//   - its own ResponderPosition (dead reckoning) once a mission second: it keeps the
//     firefighter heard at incident command, and its writer's liveliness (MANUAL_BY_TOPIC,
//     asserted every odometry step, device_position_options) is the firefighter's link there
//     (the daemon's map-aided positions come from another writer);
//   - the daemon's map-aided ResponderPosition of this firefighter, handed to the device.
#include <deque>
#include <memory>
#include <mutex>

#include "sarloc/core/responder/alarm.hpp"
#include "sarloc/core/responder/odometry.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/rate_limited_log.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"
#include "sarloc/dds/writer_authority.hpp"

namespace sarloc::dds {

struct FirefighterNodeConfig {
  std::string responder_id;
  std::string team = "team";
  std::vector<std::string> partitions;  ///< the sector's DDS partition(s); empty = default
  /// Mission seconds without a map-aided position from the daemon before the device says it
  /// is dead reckoning on its own (rescuer.fallback_timeout_s).
  double daemon_timeout_s = 3.0;
  void validate() const;  ///< throws ConfigError naming the key
};

class FirefighterNode {
 public:
  FirefighterNode(std::shared_ptr<Participant> participant, FirefighterNodeConfig config, MissionClock clock);
  ~FirefighterNode();
  FirefighterNode(const FirefighterNode&) = delete;
  FirefighterNode& operator=(const FirefighterNode&) = delete;

  bool publish_odometry(const responder::Odometry& odometry);
  bool publish_alarm(const responder::ResponderAlarm& alarm);
  bool publish_position(const responder::ResponderPosition& position);
  /// The daemon's positions of this firefighter received since the previous call, oldest first.
  std::vector<responder::ResponderPosition> take_fixes();
  /// No map-aided position from the daemon for daemon_timeout_s (or none yet).
  bool daemon_silent() const;
  /// Waits until a core daemon's odometry reader matched (or `timeout` passes).
  bool wait_for_daemon(std::chrono::milliseconds timeout) const;
  /// The device stops in order: says so on DDS (sign_off.hpp). Not called on a crash or error.
  bool sign_off(std::chrono::milliseconds timeout);

 private:
  FirefighterNodeConfig config_;
  MissionClock clock_;
  std::shared_ptr<Participant> participant_;
  WriterAuthority authority_;  ///< with DDS Security: only a core daemon writes estimates and fixes for us
  RateLimitedLog refusals_{std::chrono::seconds(5)};
  Writer<::sarloc::Odometry> odometry_writer_;
  Writer<::sarloc::ResponderAlarm> alarm_writer_;
  Writer<::sarloc::ResponderPosition> position_writer_;
  mutable std::mutex mutex_;
  std::deque<responder::ResponderPosition> fixes_;  // under mutex_
  TimestampNs last_fix_at_ = 0;                     // mission time of arrival; under mutex_
  TimestampNs newest_fix_stamp_ = 0;                // a fix no newer is the daemon's copy of one taken; under mutex_
  std::unique_ptr<Reader<::sarloc::ResponderPosition>> position_reader_;
};

}  // namespace sarloc::dds
