#pragma once
// The DDS side of sarloc-replay: re-publishes a recording's payloads, untouched, on their
// topics with their recorded timing (scaled by a rate), between two mission times, for chosen
// topics, or only the raw inputs the devices measured.
//
// Timing: a message recorded at wall time L goes out at wall_start + (L - L_start) / rate,
// where L_start is the recorded wall time of mission second start_s. Fresh nodes that should
// live on the recorded timeline get the recorded epoch, reached at epoch_wall_ns() (their
// --epoch-ns / --epoch-wall-ns / --speedup options).
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "sarloc/dds/participant.hpp"
#include "sarloc/recording/mcap_reader.hpp"

namespace sarloc::dds {

struct ReplayConfig {
  std::string recording;
  double rate = 1.0;  ///< 2: twice as fast as recorded
  /// Mission seconds (from the recording's epoch) to start and stop at.
  double start_s = 0.0;
  double end_s = std::numeric_limits<double>::infinity();
  /// Topic names to replay (empty: every sarloc topic in the file).
  std::vector<std::string> topics;
  /// Only what the devices measured or decided themselves: field measurements, odometry, the
  /// devices' own positions (not the daemon's map-aided ones), their own victim estimates
  /// (from_device) and their alarms. What a fresh core daemon and incident command need to
  /// compute everything else again.
  bool inputs_only = false;

  /// Throws ConfigError naming the field, the value and the rule.
  void validate() const;
};

struct ReplayResult {
  recording::McapReadResult read;
  std::uint64_t published = 0;
  std::uint64_t filtered = 0;       ///< skipped by topic, time or inputs_only
  std::uint64_t write_failures = 0;
  std::uint64_t undecodable = 0;    ///< inputs_only could not tell what it was: not sent
  std::map<std::string, std::uint64_t> published_by_topic;
};

/// The recording's epoch and speedup (its sarloc.recording metadata; without them, the first
/// message and 1).
struct RecordedTimeline {
  std::int64_t epoch_ns = 0;
  double speedup = 1.0;
};
RecordedTimeline recorded_timeline(const std::string& recording);
/// The same from a "sarloc.recording" metadata record's values (epoch 0 when it has none; a
/// speedup that is not a positive number is 1). Throws ConfigError when a value does not parse.
RecordedTimeline timeline_of(const recording::StringMap& metadata);

class Replayer {
 public:
  /// Creates one writer per topic to replay (from the topics' XML profiles).
  Replayer(std::shared_ptr<Participant> participant, ReplayConfig config);
  ~Replayer();
  Replayer(const Replayer&) = delete;
  Replayer& operator=(const Replayer&) = delete;

  /// Wall time (ns) at which a node's clock must read the recorded epoch, for a replay
  /// starting at `wall_start_ns`.
  std::int64_t epoch_wall_ns(std::int64_t wall_start_ns) const;
  const RecordedTimeline& timeline() const { return timeline_; }

  /// Publishes from `wall_start_ns` on; returns early when `stop` says so (checked between
  /// messages). `on_progress(mission_s)` after each message.
  ReplayResult run(std::int64_t wall_start_ns, const std::function<bool()>& stop,
                   const std::function<void(double)>& on_progress = {});

 private:
  struct TopicWriter;
  bool wanted(const std::string& topic, const recording::Message& message, ReplayResult& result) const;

  std::shared_ptr<Participant> participant_;
  ReplayConfig config_;
  RecordedTimeline timeline_;
  std::map<std::string, std::unique_ptr<TopicWriter>> writers_;
};

}  // namespace sarloc::dds
