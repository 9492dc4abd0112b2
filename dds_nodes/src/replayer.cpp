#include "sarloc/core/common/time_units.hpp"
#include "sarloc/dds/replayer.hpp"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/dds/dds_error.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/topic_catalog.hpp"
#include "sarloc/dds/topics.hpp"

namespace sarloc::dds {

namespace fdds = eprosima::fastdds::dds;

namespace {

// The topics whose every sample a device measured or decided itself; responder_position and
// victim_estimate are inputs only for some samples (wanted()).
const std::vector<std::string> kInputTopics = {"sarloc/field_measurement", "sarloc/odometry", "sarloc/responder_alarm",
                                               "sarloc/responder_position", "sarloc/victim_estimate"};

// A writer listener of its own: Fast DDS 2.9 can crash on a writer without one (NOTES).
class QuietWriterListener : public fdds::DataWriterListener {};

}  // namespace

void ReplayConfig::validate() const {
  if (recording.empty()) throw ConfigError("replay.recording is empty");
  if (!std::isfinite(rate) || rate <= 0.0 || rate > 1000.0) {
    throw ConfigError("replay.rate = " + config_value(rate) + ": must be in (0, 1000]");
  }
  if (!std::isfinite(start_s) || start_s < 0.0) throw ConfigError("replay.start_s = " + config_value(start_s) + ": must be >= 0");
  if (!(end_s > start_s)) throw ConfigError("replay.end_s = " + config_value(end_s) + ": must be > start_s");
  for (const auto& name : topics) {
    if (find_catalog_topic(name) == nullptr) throw ConfigError("replay.topics: '" + name + "' is not a sarloc topic");
  }
}

RecordedTimeline timeline_of(const recording::StringMap& metadata) {
  RecordedTimeline timeline;
  try {
    if (metadata.count("epoch_ns")) timeline.epoch_ns = std::stoll(metadata.at("epoch_ns"));
    if (metadata.count("speedup")) timeline.speedup = std::stod(metadata.at("speedup"));
  } catch (const std::exception&) {
    throw ConfigError("the recording's epoch_ns/speedup metadata do not parse");
  }
  if (!(timeline.speedup > 0.0) || !std::isfinite(timeline.speedup)) timeline.speedup = 1.0;
  return timeline;
}

RecordedTimeline recorded_timeline(const std::string& recording) {
  RecordedTimeline timeline;
  std::uint64_t first = 0;
  recording::McapVisitor visitor;
  visitor.on_metadata = [&](const recording::Metadata& m) {
    if (m.name != "sarloc.recording") return;
    try {
      timeline = timeline_of(m.values);
    } catch (const ConfigError& error) {
      throw ConfigError("recording '" + recording + "': " + error.what());
    }
  };
  visitor.on_message = [&](const recording::Message& m) {
    if (first == 0) first = m.log_time_ns;
  };
  recording::read_mcap(recording, visitor);
  if (timeline.epoch_ns == 0) timeline.epoch_ns = static_cast<std::int64_t>(first);
  return timeline;
}

struct Replayer::TopicWriter {
  fdds::Topic* topic = nullptr;
  fdds::Publisher* publisher = nullptr;
  fdds::DataWriter* writer = nullptr;
  QuietWriterListener listener;
};

Replayer::Replayer(std::shared_ptr<Participant> participant, ReplayConfig config)
    : participant_(std::move(participant)), config_(std::move(config)) {
  config_.validate();
  timeline_ = recorded_timeline(config_.recording);
  for (const auto& topic : topic_catalog()) {
    if (!config_.topics.empty() && std::find(config_.topics.begin(), config_.topics.end(), topic.name) == config_.topics.end()) continue;
    if (config_.inputs_only && std::find(kInputTopics.begin(), kInputTopics.end(), topic.name) == kInputTopics.end()) continue;
    auto w = std::make_unique<TopicWriter>();
    w->topic = participant_->topic(topic.name, fdds::TypeSupport(new RawPubSubType(topic.make_type())));
    w->publisher = participant_->get()->create_publisher(participant_->get()->get_default_publisher_qos());
    if (w->publisher == nullptr) throw DdsError("replay: cannot create a publisher for '" + topic.name + "'");
    // Device positions are asserted MANUAL_BY_TOPIC, which matches every reader of the topic.
    const std::string profile = topic.name == "sarloc/responder_position" ? "responder_position.device.writer" : topic.profile + ".writer";
    w->writer = w->publisher->create_datawriter_with_profile(w->topic, profile, &w->listener);
    if (w->writer == nullptr) throw DdsError("replay: cannot create the writer of '" + topic.name + "' from '" + profile + "'");
    writers_[topic.name] = std::move(w);
  }
}

Replayer::~Replayer() {
  for (auto& [name, w] : writers_) {
    if (w->writer != nullptr) w->publisher->delete_datawriter(w->writer);
    if (w->publisher != nullptr) participant_->get()->delete_publisher(w->publisher);
  }
}

std::int64_t Replayer::epoch_wall_ns(std::int64_t wall_start_ns) const {
  return wall_start_ns - seconds_to_ns(config_.start_s / timeline_.speedup / config_.rate);
}

bool Replayer::wanted(const std::string& topic, const recording::Message& message, ReplayResult& result) const {
  if (writers_.count(topic) == 0) return false;
  if (!config_.inputs_only) return true;
  if (topic == "sarloc/responder_position") {
    ::sarloc::ResponderPosition p;
    if (!decode_payload<::sarloc::ResponderPositionPubSubType>(message.data, p)) {
      ++result.undecodable;
      return false;
    }
    return p.source() != ::sarloc::POSITION_MAP_AIDED;  // the daemon's answer, not an input
  }
  if (topic == "sarloc/victim_estimate") {
    ::sarloc::VictimEstimate e;
    if (!decode_payload<::sarloc::VictimEstimatePubSubType>(message.data, e)) {
      ++result.undecodable;
      return false;
    }
    return e.from_device();
  }
  return true;
}

ReplayResult Replayer::run(std::int64_t wall_start_ns, const std::function<bool()>& stop,
                           const std::function<void(double)>& on_progress) {
  ReplayResult result;
  std::map<std::uint16_t, std::string> topics;
  const double speedup = timeline_.speedup;
  const std::int64_t epoch_wall = epoch_wall_ns(wall_start_ns);
  bool stopped = false;
  recording::McapVisitor visitor;
  visitor.on_channel = [&](const recording::Channel& c) { topics[c.id] = c.topic; };
  visitor.on_message = [&](const recording::Message& m) {
    if (stopped) return;
    const double mission_s = 1e-9 * speedup * (static_cast<double>(m.log_time_ns) - static_cast<double>(timeline_.epoch_ns));
    const auto topic = topics.find(m.channel_id);
    if (topic == topics.end() || mission_s < config_.start_s || mission_s > config_.end_s || !wanted(topic->second, m, result)) {
      ++result.filtered;
      return;
    }
    // Recorded wall offset from the epoch, scaled by the rate, from the replay's own epoch.
    const auto due = epoch_wall + static_cast<std::int64_t>((static_cast<double>(m.log_time_ns) - static_cast<double>(timeline_.epoch_ns)) / config_.rate);
    while (true) {
      if (stop && stop()) {
        stopped = true;
        return;
      }
      const std::int64_t wait = due - MissionClock::wall_now_ns();
      if (wait <= 0) break;
      std::this_thread::sleep_for(std::chrono::nanoseconds(std::min<std::int64_t>(wait, 100'000'000)));
    }
    RawSample sample{m.data};
    if (writers_.at(topic->second)->writer->write(&sample)) {
      ++result.published;
      ++result.published_by_topic[topic->second];
    } else {
      ++result.write_failures;
    }
    if (on_progress) on_progress(mission_s);
  };
  result.read = recording::read_mcap(config_.recording, visitor);
  return result;
}

}  // namespace sarloc::dds
