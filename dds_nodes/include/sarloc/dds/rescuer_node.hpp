#pragma once
// The DDS side of a rescuer's device (sarloc-rescuer).
//
// Every epoch: publish the step's odometry, the GNSS fix and the field samples; wait briefly
// for the core daemon's guidance for this epoch; pick the guidance to follow.
//
// The device always runs the same RescuerSearch as the daemon on its own samples (a hot
// standby: a few ms per epoch). So when the daemon is unreachable (no guidance for
// fallback_timeout_s, or every core daemon's NodeStatus liveliness lost) the rescuer keeps being guided with the whole
// search history, and publishes its own estimates so incident command keeps seeing victims.
// When the daemon comes back (possibly restarted, with an empty filter) its guidance is
// followed again only once its estimate of the target is at least as far along
// (INITIALISING < MULTIMODAL < CONVERGED < LOCATED < FOUND) as the device's own.
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "sarloc/core/avalanche/rescuer_search.hpp"
#include "sarloc/core/incident/responder_position.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"

namespace sarloc::dds {

struct RescuerNodeConfig {
  std::string rescuer_id;
  std::string team = "team";
  std::vector<std::string> partitions;  ///< the sector's DDS partition(s); empty = default
  avalanche::RescuerSearchConfig search;  ///< the on-device (fallback) search
  double fallback_timeout_s = 3.0;      ///< mission time without daemon guidance before local guidance
  /// Wall time to wait for the daemon's answer each epoch (only while it is reachable); keep it
  /// well below an epoch's wall duration (MissionConfig caps it at half an epoch).
  double guidance_wait_s = 0.25;

  /// Throws ConfigError naming the key ("rescuer.fallback_timeout_s = 0: must be in (0, 600]").
  void validate() const;
};

enum class GuidanceSource : std::uint8_t { kNone = 0, kDaemon = 1, kLocal = 2 };
const char* to_string(GuidanceSource source);

struct EpochResult {
  std::optional<avalanche::Guidance> guidance;  ///< what to do now (nullopt: no signal yet)
  GuidanceSource source = GuidanceSource::kNone;
  bool daemon_reachable = false;
  std::map<std::uint32_t, avalanche::EstimatorStatus> signals;  ///< status of every signal (followed source)
  double latency_ms = -1.0;  ///< measurement publish -> daemon guidance arrival (wall), -1 if none
};

class RescuerNode {
 public:
  RescuerNode(std::shared_ptr<Participant> participant, RescuerNodeConfig config, MissionClock clock);
  ~RescuerNode();
  RescuerNode(const RescuerNode&) = delete;
  RescuerNode& operator=(const RescuerNode&) = delete;

  /// One epoch: `odometry` is the motion since the previous epoch (none on the first),
  /// `gnss` the fix (if any), `measurements` this epoch's field samples (one per signal).
  EpochResult epoch(const std::vector<avalanche::Odometry>& odometry,
                    const std::optional<incident::ResponderPosition>& gnss,
                    const std::vector<avalanche::FieldMeasurement>& measurements);

  /// Waits until the daemon's readers matched this device's writers (or `timeout` passes), so
  /// the first samples are not published to nobody. Returns whether they matched.
  bool wait_for_daemon(std::chrono::milliseconds timeout) const;

  /// Times the rescuer switched from daemon to local guidance.
  int fallbacks() const { return fallbacks_; }
  const avalanche::RescuerSearch& local_search() const { return local_; }

 private:
  struct Remote {
    std::optional<avalanche::Guidance> guidance;
    std::uint64_t guidance_sequence = 0;
    TimestampNs guidance_mission_time = 0;
    std::int64_t guidance_wall_ns = 0;
    /// Any answer of the daemon (estimate or guidance) tells it is alive and which epoch it reached.
    std::uint64_t answered_sequence = 0;
    TimestampNs answered_mission_time = 0;
    struct SignalStatus {
      avalanche::EstimatorStatus status = avalanche::EstimatorStatus::kInitialising;
      std::uint64_t sequence = 0;  ///< measurement it answers
    };
    std::map<std::uint32_t, SignalStatus> status;
  };

  RescuerNodeConfig config_;
  MissionClock clock_;
  std::shared_ptr<Participant> participant_;
  avalanche::RescuerSearch local_;
  Writer<::sarloc::FieldMeasurement> measurement_writer_;
  Writer<::sarloc::Odometry> odometry_writer_;
  Writer<::sarloc::VictimEstimate> estimate_writer_;  // only while the daemon is unreachable
  Writer<::sarloc::ResponderPosition> position_writer_;
  std::mutex mutex_;
  std::condition_variable cv_;
  Remote remote_;
  std::map<std::uint32_t, bool> found_elsewhere_;
  std::vector<eprosima::fastrtps::rtps::InstanceHandle_t> live_core_writers_;  // NodeStatus writers of kind CORE
  bool seen_core_ = false;
  bool was_reachable_ = false;
  int fallbacks_ = 0;
  TimestampNs started_ = 0;
  std::unique_ptr<Reader<::sarloc::Guidance>> guidance_reader_;
  std::unique_ptr<Reader<::sarloc::VictimEstimate>> estimate_reader_;
  std::unique_ptr<Reader<::sarloc::FusedVictim>> victim_reader_;
  std::unique_ptr<Reader<::sarloc::NodeStatus>> core_status_reader_;
};

}  // namespace sarloc::dds
