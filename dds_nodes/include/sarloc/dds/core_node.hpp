#pragma once
// sarloc-core's DDS node: one participant for the whole daemon, every responder of its sector,
// whatever its role.
//
// Listener threads only convert and enqueue. Each responder is pinned to one worker thread
// (hash of its id), which owns that responder's estimator::SampleSequencer and, through it,
// the estimator chosen by the responder's role (estimator::make_estimator). So a responder's
// samples are processed in order and no estimator is touched by two threads. When a sample is
// processed (waiting for its epoch's odometry, unknown motion in place of odometry that never
// came) is the sequencer's rule; what is refused is the estimator's. This node publishes what
// they produce (victim estimates, guidance, positions), counts refusals by reason in
// NodeStatus and logs them once per (responder, reason) per warning interval.
//
// Who gets state at all is estimator::ResponderRoster's rule, applied inside DDS by a content
// filter on the input readers (responder_filter.hpp): a sample of an id the roster refuses
// takes no instance in a reader's history and no place in a worker's queue. Idle responders'
// state is released on the status thread's period. While a worker's queue holds a sample
// longer than core.busy_wait_s, no new responder is admitted (estimator::BusyGate): the
// responders served already keep their latency. The position writer has a lifespan, so a
// firefighter who falls silent cannot leave old samples in its history for the rest of the
// incident; his last position is written again within it (estimator::PositionRefresh).
#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <thread>
#include <variant>
#include <vector>

#include "sarloc/core/estimator/busy_gate.hpp"
#include "sarloc/core/estimator/estimator_journal.hpp"
#include "sarloc/core/estimator/make_estimator.hpp"
#include "sarloc/core/estimator/position_refresh.hpp"
#include "sarloc/core/estimator/responder_roster.hpp"
#include "sarloc/core/estimator/sample_sequencer.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/rate_limited_log.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/reject_counters.hpp"
#include "sarloc/dds/sample_readers.hpp"
#include "sarloc/dds/writer.hpp"
#include "sarloc/dds/writer_authority.hpp"

namespace sarloc::dds {

struct CoreNodeConfig {
  std::string node_id = "sarloc-core";
  estimator::EstimatorConfigs estimators;
  /// Role of each responder the mission lists; others get default_role.
  std::map<std::string, estimator::ResponderRole> roles;
  estimator::ResponderRole default_role = estimator::ResponderRole::kAvalancheRescuer;
  /// DDS partitions (sectors) whose responders this instance serves; empty = default partition.
  std::vector<std::string> partitions;
  /// Who is served (the sector's roster, or any id up to a maximum) and when idle state goes.
  estimator::ResponderRosterConfig roster;
  /// When the daemon is too busy to admit a new responder.
  estimator::BusyGateConfig busy;
  unsigned workers = 2;              ///< threads running estimators (this machine: 2 cores)
  std::size_t queue_limit = 4096;    ///< samples waiting per worker before the oldest are dropped
  double status_period_s = 1.0;      ///< NodeStatus publication period (wall clock)
  double warning_interval_s = 5.0;   ///< one warning per (responder, reason) per interval
  /// A sample of a new epoch waits at most this long (wall) for the odometry up to its stamp
  /// (estimator::SampleSequencer); then it is processed with unknown motion in its place.
  double odometry_wait_s = 0.25;
  /// Hand-over between sectors' daemons (docs/architecture.md): each responder's estimator keeps
  /// the journal of its calls, up to this many (0: none, and no hand-over); a daemon meeting a
  /// responder asks for it on sarloc/rescuer_handover, and the one holding it hands it over.
  std::size_t handover_journal_entries = 0;

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
  /// Responders whose estimator this daemon handed to another sector's, and took from one.
  std::size_t handed_over() const { return handed_over_.load(); }
  std::size_t taken_over() const { return taken_over_.load(); }

  /// The daemon stops in order: stops taking samples, then disposes its NodeStatus instance
  /// (sign_off.hpp) so that devices log a stop, not a loss. Call once, last, before the
  /// destructor; not on an error.
  bool sign_off(std::chrono::milliseconds timeout);

 private:
  struct MarkDone {
    std::string rescuer_id;
    std::uint32_t signal_id = 0;
  };
  struct Evict {
    std::string rescuer_id;
    bool shed = false;  ///< released because those served were too many (BusyGate::note_shed), not idle
  };
  /// Signals whose victims incident command sends another rescuer to (the search plan).
  struct LeaveToOthers {
    std::string rescuer_id;
    std::set<std::uint32_t> signal_ids;
    TimestampNs until = 0;
  };
  /// A device's own position (its dead reckoning): a start for a filter that meets the
  /// responder mid-search (ResponderEstimator::hint_position).
  struct PositionHint {
    responder::ResponderPosition own;
  };
  /// Another daemon met this responder (its request): hand its estimator over, if here.
  struct HandOverTo {
    std::string rescuer_id;
    std::string to_node;
  };
  /// Another daemon handed this responder's estimator over (its journal).
  struct TakeOver {
    std::string rescuer_id;
    std::string from_node;
    estimator::EstimatorJournal journal;
  };
  /// The daemon this responder was handed to took him over: release his state here.
  struct HandedOver {
    std::string rescuer_id;
    std::string by_node;
  };
  using Work = std::variant<responder::Odometry, estimator::SensorSample, MarkDone, Evict, LeaveToOthers, PositionHint,
                            HandOverTo, TakeOver, HandedOver>;
  struct Queued {
    Work work;
    std::chrono::steady_clock::time_point at;  ///< enqueued: its wait tells the BusyGate
  };
  struct Worker {
    std::thread thread;
    std::mutex mutex;
    std::condition_variable cv;
    std::deque<Queued> queue;
    std::map<std::string, estimator::SampleSequencer> responders;  // only this worker's thread touches them
    /// Responders whose estimator was handed to another daemon, with the latest stamp it had
    /// taken: their samples stamped no later are stragglers of the switch and are dropped. The
    /// state stays until that daemon says it took the responder over (HandedOver).
    std::map<std::string, TimestampNs> handed_away;
    std::atomic<std::int64_t> busy_ns{0};                          ///< steady time spent handling and publishing
    std::int64_t busy_noted_ns = 0;  ///< busy_ns at the last note_worker_load (status thread)
    /// Each responder's share of this worker's time: handling seconds, halved every second (so
    /// about the last two seconds' worth). Only this worker's thread touches it.
    std::map<std::string, double> cost_s;
    std::chrono::steady_clock::time_point cost_halved_at;
  };

  /// The input readers' filter: does the roster serve this sample's responder? Counts and logs a refusal.
  bool admit(const ResponderSample& sample);
  /// `droppable` false: never pushed out of a full queue (a journal taken over, its release).
  void enqueue(const std::string& rescuer_id, Work work, bool droppable = true);
  /// Queues a hint unless the worker's queue is half full (it never displaces a sample).
  void enqueue_hint(const std::string& rescuer_id, PositionHint hint);
  /// Queues the release of every idle responder's state on its worker.
  void evict_idle();
  /// Called by `worker`'s own thread when one of its samples waited `waited`, over
  /// core.busy_shed_wait_s (BusyGate::note_shed): releases the responders of this worker
  /// admitted last, their waiting samples with them, until they took a share of its time that
  /// drains such a wait within kDrainS; their state goes first thing.
  void release_newest(Worker& worker, std::chrono::steady_clock::duration waited);
  Worker& worker_of(const std::string& rescuer_id);
  static std::string responder_of(const Work& work);
  void run_worker(Worker& worker);
  void handle(Worker& worker, Work& work);
  /// The responder's sequencer, created on its first sample (the roster admitted it already).
  estimator::SampleSequencer& sequencer_for(Worker& worker, const std::string& rescuer_id);
  /// Publishes the answers, counts the rest; clears the report.
  void publish(estimator::SequencerReport& report);
  void reject(const std::string& rescuer_id, const std::string& reason, const std::string& detail);
  void publish_status();
  void hand_over(Worker& worker, const HandOverTo& request);
  void take_over(Worker& worker, TakeOver& handed);
  void release_handed(Worker& worker, const HandedOver& taken);
  /// Erases a responder's state on its worker (`it` in worker.responders), with its filters' count.
  void drop_state(Worker& worker, std::map<std::string, estimator::SampleSequencer>::iterator it);
  /// A sample or step of a responder handed away that is no later than its hand-over: dropped.
  bool straggler(Worker& worker, const std::string& rescuer_id, TimestampNs stamp);
  /// Writes again the last position of every responder whose positions stopped (status thread).
  void refresh_silent_positions();
  /// Tells the BusyGate the busiest worker's share of the time since the last call (status thread).
  void note_worker_load();
  void stop();  // the readers, then the threads; once (sign_off, then the destructor)
  void stop_threads();

  CoreNodeConfig config_;
  std::shared_ptr<Participant> participant_;
  WriterAuthority authority_;  ///< with DDS Security: only a responder's device writes its samples
  RejectCounters counters_;
  RateLimitedLog warnings_;
  std::atomic<std::size_t> rescuers_served_{0};
  std::atomic<std::size_t> active_filters_{0};
  std::atomic<std::size_t> handed_over_{0};
  std::atomic<std::size_t> taken_over_{0};
  std::mutex roster_mutex_;  // listener threads admit, the status thread evicts
  estimator::ResponderRoster roster_;
  estimator::BusyGate busy_gate_;

  Writer<::sarloc::VictimEstimate> estimate_writer_;
  Writer<::sarloc::Guidance> guidance_writer_;
  Writer<::sarloc::ResponderPosition> position_writer_;
  Writer<::sarloc::ResponderCandidates> candidates_writer_;
  /// Each responder's last position, kept within the position writer's lifespan (null when
  /// the writer keeps its samples for ever).
  std::unique_ptr<estimator::PositionRefresh> position_refresh_;
  Writer<::sarloc::NodeStatus> status_writer_;
  Writer<::sarloc::RescuerHandover> handover_writer_;  ///< default partition: every sector's daemon reads it
  std::vector<std::unique_ptr<Worker>> workers_;
  std::atomic<bool> stopping_{false};
  std::thread status_thread_;
  std::chrono::steady_clock::time_point load_noted_at_;  ///< status thread only
  /// Rescuers with signals handed over in the last plan (plan reader thread only): those no
  /// longer in it get an empty set.
  std::set<std::string> handed_over_rescuers_;
  // Readers last: they start calling back as soon as they exist.
  std::unique_ptr<SampleReaders> sample_readers_;
  std::unique_ptr<Reader<::sarloc::Odometry>> odometry_reader_;
  std::unique_ptr<Reader<::sarloc::FusedVictim>> victim_reader_;
  std::unique_ptr<Reader<::sarloc::SearchPlan>> plan_reader_;
  std::unique_ptr<Reader<::sarloc::ResponderPosition>> device_position_reader_;
  std::unique_ptr<Reader<::sarloc::RescuerHandover>> handover_reader_;
};

}  // namespace sarloc::dds
