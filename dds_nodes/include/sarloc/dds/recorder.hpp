#pragma once
// The DDS side of sarloc-record: one raw reader per recorded topic (the payload exactly as it
// arrived, encapsulation included), a queue, and one thread that writes the MCAP file.
//
//   Recorder recorder(participant, config);  // starts recording at once
//   ... recorder.failed() / recorder.counters() ...
//   recorder.close();                        // writes the summary; the file is complete
//
// What the listener threads do: copy the payload and its times into the queue (nothing else).
// What the writer thread does: everything with the file: chunks, flushes every
// flush_period_s, rotation, the per-flush status message, and the error that stops it.
//
// Besides the topics, two JSON channels of its own: "sarloc/recorder_status" (counters per
// topic, once per flush) and "sarloc/recorder_events" (the first sample of each participant on
// each topic: {topic, participant, sequence, log_time_ns}). MCAP messages do not say who wrote
// them; the events do, so that a report can tell an incident-command failover (the picture
// written by another participant) or a daemon restart.
#include <fastdds/dds/subscriber/DataReader.hpp>

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/raw_topic_readers.hpp"
#include "sarloc/recording/mcap_records.hpp"

namespace sarloc::dds {

struct RecorderConfig {
  /// The first file; rotation writes "<stem>-001.mcap", "<stem>-002.mcap", ... beside it.
  std::string output_path;
  /// Topic names to record (empty: every sarloc topic), and topic names never to record.
  std::vector<std::string> allow;
  std::vector<std::string> block;
  /// Besides the default partition, also record these (sectors); "*" records every named one.
  std::vector<std::string> partitions = {"*"};
  recording::Compression compression = recording::Compression::kZstd;
  /// At most this long between a sample's arrival and its bytes reaching the kernel: what a
  /// SIGKILL can lose.
  double flush_period_s = 1.0;
  /// Start a new file past this size or this duration (0: never).
  double rotate_size_mb = 0.0;
  double rotate_duration_s = 0.0;
  /// Samples waiting for the writer thread beyond this are dropped and counted (queue_full).
  double max_queue_mb = 256.0;
  bool sync_on_flush = false;
  /// Written as the "sarloc.recording" metadata record of every file (mission, version, ...).
  recording::StringMap metadata;

  /// Throws ConfigError naming the field, the value and the rule.
  void validate() const;
};

/// Per topic: what arrived, what reached the file, and what DDS lost or refused.
struct TopicCounters {
  std::uint64_t received = 0;
  std::uint64_t written = 0;
  std::uint64_t lost = 0;  ///< DDS on_sample_lost: a reliable gap or a best-effort drop
  std::map<std::string, std::uint64_t> rejected;  ///< by reason (DDS resource limits, queue_full)
  std::uint64_t incompatible_qos = 0;             ///< writers that could not match the recorder
};

class Recorder {
 public:
  Recorder(std::shared_ptr<Participant> participant, RecorderConfig config);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  /// Stops the readers, writes what is queued, the counters and the summary. Throws
  /// RecordingError if the file cannot be finished.
  void close();

  /// Non-empty once writing failed (disk full, unwritable path): recording has stopped.
  std::string error() const;
  std::map<std::string, TopicCounters> counters() const;
  /// Files written so far (the current one last).
  std::vector<std::string> files() const;
  /// Readers matched to at least one writer, per topic.
  std::map<std::string, int> matched_writers() const;

 private:
  struct Channel;
  struct Queued {
    std::size_t channel = 0;
    std::uint32_t sequence = 0;
    std::uint64_t log_time_ns = 0;
    std::uint64_t publish_time_ns = 0;
    std::array<std::uint8_t, 12> participant{};  ///< the writer's GUID prefix
    std::vector<std::uint8_t> bytes;
  };
  void enqueue(Queued item);
  void count_lost(std::size_t channel, std::uint64_t count);
  void count_rejected(std::size_t channel, const std::string& reason);
  void count_incompatible(std::size_t channel);
  void writer_loop();
  std::string next_file_path();

  std::shared_ptr<Participant> participant_;
  RecorderConfig config_;
  std::vector<std::unique_ptr<Channel>> channels_;
  std::unique_ptr<RawTopicReaders> readers_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Queued> queue_;
  std::size_t queued_bytes_ = 0;
  bool stopping_ = false;
  std::string error_;
  std::vector<std::string> files_;
  std::map<std::string, TopicCounters> counters_;
  std::thread writer_thread_;
  bool closed_ = false;
};

/// Mission recordings are named after their start: "<dir>/<prefix>-YYYYmmddTHHMMSSZ.mcap".
std::string timestamped_recording_path(const std::string& directory, const std::string& prefix);

}  // namespace sarloc::dds
