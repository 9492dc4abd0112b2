#pragma once
// EchoNode: the DDS floor under sarloc-core's measurement -> estimate latency.
//
// It joins the domain exactly as sarloc-core does (one participant from the mission's profile,
// the topics' XML QoS profiles, the daemon's partitions, and the same inbound traffic: it reads
// the odometry too, and drops it) but estimates nothing: each FieldMeasurement is answered at
// once by a VictimEstimate with the same rescuer_id, signal_id, stamp and sequence.
// sarloc-bench-latency runs it as its own process (sarloc-bench-echo) at the same load points
// as the daemon; whatever the daemon takes on top of the echo is the daemon's own.
//
//   auto participant = std::make_shared<dds::Participant>(participant_config);
//   EchoNode echo(participant, EchoNodeConfig{});  // answers until destroyed
//
// Handoff kListener answers on the Fast DDS listener thread: the transport's floor.
// kQueue hands each sample to one worker thread through a mutex, a deque and a condition
// variable, as sarloc-core's listener hands samples to its workers: the difference between the
// two is the cost of that hand-off (one more thread wake-up per sample). kWaitSet has no
// listener: one worker waits on the reader's DATA_AVAILABLE status condition in a DDS WaitSet
// and takes the samples itself (the other way to get samples onto the node's own thread).
#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <fastdds/dds/core/condition/GuardCondition.hpp>

#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"

namespace sarloc::bench {

enum class EchoHandoff { kListener, kQueue, kWaitSet };

const char* to_string(EchoHandoff handoff);
/// "listener", "queue" or "waitset"; throws ConfigError naming the value otherwise.
EchoHandoff parse_echo_handoff(const std::string& text);

struct EchoNodeConfig {
  /// NodeStatus.node_id (kind NODE_CORE: it stands in for the daemon).
  std::string node_id = "sarloc-bench-echo";
  EchoHandoff handoff = EchoHandoff::kListener;
  /// DDS partitions, as the daemon's (core.partitions of its sector); empty = default partition.
  std::vector<std::string> partitions;
  double status_period_s = 1.0;  ///< NodeStatus period (wall): CPU and memory for the bench

  /// Throws ConfigError naming the key ("echo.status_period_s = 0: must be in (0, 60]").
  void validate() const;
};

class EchoNode {
 public:
  EchoNode(std::shared_ptr<dds::Participant> participant, EchoNodeConfig config);
  ~EchoNode();
  EchoNode(const EchoNode&) = delete;
  EchoNode& operator=(const EchoNode&) = delete;

  std::uint64_t echoed() const { return echoed_.load(); }
  std::uint64_t refused() const { return refused_.load(); }

 private:
  void answer(const ::sarloc::FieldMeasurement& measurement);
  void run_worker();
  void run_waitset();
  void run_status();
  void stop_threads();

  EchoNodeConfig config_;
  std::shared_ptr<dds::Participant> participant_;
  std::atomic<std::uint64_t> echoed_{0};
  std::atomic<std::uint64_t> refused_{0};  ///< write() refused by DDS

  dds::Writer<::sarloc::VictimEstimate> estimate_writer_;
  dds::Writer<::sarloc::NodeStatus> status_writer_;
  std::atomic<bool> stopping_{false};
  std::mutex mutex_;
  std::condition_variable cv_;         // worker: a sample waits
  std::condition_variable status_cv_;  // status thread: stop
  std::deque<::sarloc::FieldMeasurement> queue_;  // kQueue only
  eprosima::fastdds::dds::GuardCondition stop_guard_;  // kWaitSet: wakes the worker to stop
  std::thread worker_;                             // kQueue, kWaitSet
  std::thread status_thread_;
  // Readers last: they start calling back as soon as they exist.
  std::unique_ptr<dds::Reader<::sarloc::FieldMeasurement>> measurement_reader_;
  std::unique_ptr<dds::Reader<::sarloc::Odometry>> odometry_reader_;
};

}  // namespace sarloc::bench
