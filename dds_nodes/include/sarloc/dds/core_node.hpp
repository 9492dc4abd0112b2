#pragma once
// sarloc-core's DDS node: one participant for the whole daemon, every rescuer of its sector.
//
// Listener threads only convert and enqueue. Each rescuer is pinned to one worker thread
// (hash of its id), which owns that rescuer's RescuerSearch, so no filter is ever touched by
// two threads; a measurement waits for the odometry up to its stamp (odometry_wait_s), so
// motion and field samples are applied in time order whatever topic delivered first. Bad samples are
// refused before they reach a filter, counted by reason in NodeStatus, and logged once per
// (rescuer, reason) per warning interval.
#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <set>
#include <memory>
#include <thread>
#include <variant>
#include <vector>

#include "sarloc/core/avalanche/rescuer_search.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/rate_limited_log.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/reject_counters.hpp"
#include "sarloc/dds/writer.hpp"

namespace sarloc::dds {

struct CoreNodeConfig {
  std::string node_id = "sarloc-core";
  avalanche::RescuerSearchConfig search;
  /// DDS partitions (sectors) whose rescuers this instance serves; empty = default partition.
  std::vector<std::string> partitions;
  /// Rescuers allowed; empty = any (up to max_rescuers). Others are rejected as unknown.
  std::vector<std::string> rescuers;
  std::size_t max_rescuers = 256;
  unsigned workers = 2;              ///< threads running filters (this machine: 2 cores)
  std::size_t queue_limit = 4096;    ///< samples waiting per worker before the oldest are dropped
  double status_period_s = 1.0;      ///< NodeStatus publication period (wall clock)
  double warning_interval_s = 5.0;   ///< one warning per (rescuer, reason) per interval
  /// Odometry and field samples travel on different topics, so a measurement can arrive
  /// before the step that precedes it. It is held until odometry covering its stamp arrived,
  /// at most this long (wall); then processed anyway and counted as "odometry_late".
  double odometry_wait_s = 0.25;

  /// Throws ConfigError naming the key ("core.workers = 0: must be in [1, 64]").
  void validate() const;
};

class CoreNode {
 public:
  CoreNode(std::shared_ptr<Participant> participant, CoreNodeConfig config);
  ~CoreNode();
  CoreNode(const CoreNode&) = delete;
  CoreNode& operator=(const CoreNode&) = delete;

  RejectCounters::Snapshot counters() const { return counters_.snapshot(); }
  std::size_t rescuers_served() const { return rescuers_served_.load(); }

 private:
  struct MarkDone {
    std::string rescuer_id;
    std::uint32_t signal_id = 0;
  };
  using Work = std::variant<avalanche::Odometry, avalanche::FieldMeasurement, MarkDone>;
  using SteadyTime = std::chrono::steady_clock::time_point;
  struct Held {
    avalanche::FieldMeasurement measurement;
    SteadyTime deadline;
  };
  struct RescuerState {
    avalanche::RescuerSearch search;
    /// interval_end of the last odometry step dealt with: accepted, refused for its values, or
    /// stood in for by unknown motion.
    TimestampNs odometry_until = 0;
    std::optional<TimestampNs> measured_at;  ///< stamp of the last processed epoch (signals share it)
    std::deque<Held> held;           ///< measurements waiting for their odometry, in arrival order
  };
  struct Worker {
    std::thread thread;
    std::mutex mutex;
    std::condition_variable cv;
    std::deque<Work> queue;
    std::map<std::string, RescuerState> rescuers;  // only this worker's thread touches them
  };

  void enqueue(const std::string& rescuer_id, Work work);
  void run_worker(Worker& worker);
  void handle(Worker& worker, Work& work);
  void process_measurement(RescuerState& state, const avalanche::FieldMeasurement& measurement);
  /// Processes held measurements whose odometry arrived (or whose wait expired).
  void release_held(RescuerState& state, SteadyTime now);
  RescuerState* state_for(Worker& worker, const std::string& rescuer_id);
  void reject(const std::string& rescuer_id, const std::string& reason, const std::string& detail);
  void publish_status();
  void stop_threads();

  CoreNodeConfig config_;
  std::shared_ptr<Participant> participant_;
  RejectCounters counters_;
  RateLimitedLog warnings_;
  std::atomic<std::size_t> rescuers_served_{0};
  std::atomic<std::size_t> active_filters_{0};
  std::mutex rescuers_mutex_;
  std::set<std::string> known_rescuers_;  // listed in the config, or admitted so far (max_rescuers)

  Writer<::sarloc::VictimEstimate> estimate_writer_;
  Writer<::sarloc::Guidance> guidance_writer_;
  Writer<::sarloc::NodeStatus> status_writer_;
  std::vector<std::unique_ptr<Worker>> workers_;
  std::atomic<bool> stopping_{false};
  std::thread status_thread_;
  // Readers last: they start calling back as soon as they exist.
  std::unique_ptr<Reader<::sarloc::FieldMeasurement>> measurement_reader_;
  std::unique_ptr<Reader<::sarloc::Odometry>> odometry_reader_;
  std::unique_ptr<Reader<::sarloc::FusedVictim>> victim_reader_;
};

}  // namespace sarloc::dds
