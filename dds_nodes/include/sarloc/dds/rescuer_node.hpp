#pragma once
// The DDS side of a responder's device (sarloc-rescuer).
//
// Every epoch: publish the step's odometry, the position fix and the sensor samples; wait
// briefly for the core daemon's answer for this epoch; follow the guidance that
// responder::GuidanceArbiter chooses (its header has the rules).
//
// The device always runs the same estimator as the daemon (estimator::make_estimator for its
// role) on its own samples: a hot standby of a few ms per epoch. So when the daemon is
// unreachable the responder keeps being guided with the whole search history, and the device
// publishes its own estimates so incident command keeps seeing victims. This node only
// converts, publishes and feeds the arbiter; the decisions are core's.
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>

#include "sarloc/core/estimator/make_estimator.hpp"
#include "sarloc/core/incident/search_plan.hpp"
#include "sarloc/core/responder/guidance_arbiter.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/rate_limited_log.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/sample_writers.hpp"
#include "sarloc/dds/writer.hpp"
#include "sarloc/dds/writer_authority.hpp"

namespace sarloc::dds {

struct RescuerNodeConfig {
  std::string rescuer_id;
  std::string team = "team";
  estimator::ResponderRole role = estimator::ResponderRole::kAvalancheRescuer;
  std::vector<std::string> partitions;    ///< the sector's DDS partition(s); empty = default
  estimator::EstimatorConfigs estimators; ///< the on-device (standby) estimator's configuration
  double fallback_timeout_s = 3.0;        ///< mission time without daemon guidance before local guidance
  /// Wall time to wait for the daemon's answer each epoch (only while it is reachable); keep it
  /// well below an epoch's wall duration (MissionConfig caps it at half an epoch).
  double guidance_wait_s = 0.25;
  /// Epochs in a row the daemon must answer before the device follows it again after guiding
  /// on its own (responder::GuidanceArbiter hysteresis).
  int rejoin_epochs = 3;

  /// Throws ConfigError naming the key ("rescuer.fallback_timeout_s = 0: must be in (0, 600]").
  void validate() const;
};

struct EpochResult {
  /// What to do now: a signal's guidance, else the plan's strip (source kPlan), else nullopt
  /// (no signal and no plan: straight ahead).
  std::optional<responder::Guidance> guidance;
  responder::GuidanceSource source = responder::GuidanceSource::kNone;
  bool daemon_reachable = false;
  std::map<std::uint32_t, responder::EstimatorStatus> signals;  ///< status of every signal (followed source)
  double latency_ms = -1.0;  ///< measurement publish -> daemon guidance arrival (wall), -1 if none
  /// Signals whose daemon estimate conflicts with the device's own (responder::GuidanceArbiter).
  std::set<std::uint32_t> conflicting_signals;
};

class RescuerNode {
 public:
  RescuerNode(std::shared_ptr<Participant> participant, RescuerNodeConfig config, MissionClock clock);
  ~RescuerNode();
  RescuerNode(const RescuerNode&) = delete;
  RescuerNode& operator=(const RescuerNode&) = delete;

  /// Publishes motion and applies it to the device's own estimator at once: a device whose
  /// separation asks its filters (SensorSource::set_consistency) moves them before it listens.
  void move(const std::vector<responder::Odometry>& odometry);
  /// One epoch: `odometry` is the motion since the previous epoch not yet given to move() (none
  /// on the first), `fix` the position fix (if any), `samples` this epoch's sensor samples.
  EpochResult epoch(const std::vector<responder::Odometry>& odometry,
                    const std::optional<responder::ResponderPosition>& fix,
                    const std::vector<estimator::SensorSample>& samples);

  /// Moves the device to another sector's partitions (it walked into that sector's area,
  /// incident::SectorAreas): its readers of the daemon's answers first, then its writers, so
  /// that it hears the new daemon from its first answer. The new daemon takes the responder's
  /// estimator over from the old one (docs/architecture.md, "Hand-over between sectors").
  /// Throws DdsError if Fast DDS refuses.
  void move_to(const std::vector<std::string>& partitions);
  /// Waits until the daemon's readers matched this device's writers (or `timeout` passes), so
  /// the first samples are not published to nobody. Returns whether they matched.
  bool wait_for_daemon(std::chrono::milliseconds timeout) const;

  /// The device stops in order: says so on DDS (sign_off.hpp) and waits up to `timeout` for
  /// incident command to have it. Not called on a crash or an error: that is a lost device.
  bool sign_off(std::chrono::milliseconds timeout);

  /// A victim of the picture: its id and position (incident frame).
  struct PictureVictim {
    std::uint32_t victim_id = 0;
    Vec3 position = Vec3::Zero();
  };
  /// The FOUND (or recovered) victim of the picture that holds this device's `signal`, if any.
  std::optional<PictureVictim> picture_victim_of(std::uint32_t signal) const;
  /// Reports a victim dug out (VictimRecovery, reported by this rescuer); false when DDS refused.
  bool report_dug_out(std::uint32_t victim_id);
  /// Victims the picture says are dug out since the last call (each once), with their final
  /// position (incident frame): a simulation switches their transmitters off.
  std::vector<std::pair<std::uint32_t, Vec3>> take_recovered();

  /// Times the responder switched from daemon to local guidance.
  int fallbacks() const;
  /// Epochs whose guidance source (daemon or device) differs from the epoch before.
  int guidance_switches() const;
  const estimator::ResponderEstimator& local_estimator() const { return *local_; }

 private:
  RescuerNodeConfig config_;
  MissionClock clock_;
  std::shared_ptr<Participant> participant_;
  WriterAuthority authority_;  ///< with DDS Security: only a core daemon writes estimates and fixes for us
  RateLimitedLog refusals_{std::chrono::seconds(5)};
  std::unique_ptr<estimator::ResponderEstimator> local_;
  SampleWriters sample_writers_;
  Writer<::sarloc::Odometry> odometry_writer_;
  Writer<::sarloc::VictimEstimate> estimate_writer_;  // only while the daemon is unreachable
  Writer<::sarloc::ResponderPosition> position_writer_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  responder::GuidanceArbiter arbiter_;  // under mutex_, epoch thread only
  /// What the listeners heard for the arbiter (the daemon's guidance and estimates, daemons seen
  /// or lost), in arrival order; the epoch thread applies it before the arbiter decides, and
  /// while it waits for the daemon's answer. Under mutex_.
  std::vector<std::function<void(responder::GuidanceArbiter&)>> arbiter_inbox_;
  static constexpr std::size_t kArbiterInboxLimit = 4096;
  void hear(std::function<void(responder::GuidanceArbiter&)> heard);  // under mutex_
  void apply_arbiter_inbox();                                         // under mutex_
  std::set<std::uint32_t> found_elsewhere_;          // signals incident command reports found; under mutex_
  std::map<std::uint32_t, PictureVictim> picture_victim_of_;  // own signal -> FOUND victim; under mutex_
  std::set<std::uint32_t> recovered_seen_;                    // under mutex_
  std::vector<std::pair<std::uint32_t, Vec3>> recovered_;     // not yet taken; under mutex_
  Writer<::sarloc::VictimRecovery> recovery_writer_;
  std::set<std::uint32_t> reported_conflicts_;       // conflicts already logged (epoch thread only)
  /// The device's own fixes, oldest first (epoch thread only): each estimate it publishes
  /// carries the one of its stamp, so that incident command can place a FOUND estimate
  /// republished with the stamp it was found at, whatever fixes a radio fade lost on the way.
  std::deque<responder::ResponderPosition> own_fixes_;
  std::optional<responder::ResponderPosition> own_fix_nearest(TimestampNs stamp) const;
  std::vector<eprosima::fastrtps::rtps::InstanceHandle_t> live_core_writers_;  // NodeStatus writers of kind CORE
  std::unique_ptr<Reader<::sarloc::Guidance>> guidance_reader_;
  std::unique_ptr<Reader<::sarloc::VictimEstimate>> estimate_reader_;
  std::unique_ptr<Reader<::sarloc::FusedVictim>> victim_reader_;
  std::unique_ptr<Reader<::sarloc::NodeStatus>> core_status_reader_;
  std::optional<incident::SearchPlanPicture> plan_;  // incident command's latest; under mutex_
  std::unique_ptr<Reader<::sarloc::SearchPlan>> plan_reader_;
};

}  // namespace sarloc::dds
