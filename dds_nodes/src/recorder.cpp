#include "sarloc/dds/recorder.hpp"

#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <set>
#include <nlohmann/json.hpp>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/dds/dds_error.hpp"
#include "sarloc/dds/idl_schemas.hpp"
#include "sarloc/dds/mission_clock.hpp"
#include "sarloc/dds/raw_topic_readers.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/topic_catalog.hpp"
#include "sarloc/recording/mcap_writer.hpp"

namespace sarloc::dds {

namespace fdds = eprosima::fastdds::dds;

namespace {

// The recorder's own channel: one JSON message per flush with the counters so far.
constexpr const char* kStatusTopic = "sarloc/recorder_status";
// The recorder's events: a participant's first sample on a topic.
constexpr const char* kEventsTopic = "sarloc/recorder_events";

std::string hex(const std::array<std::uint8_t, 12>& bytes) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (const auto b : bytes) {
    out += kHex[b >> 4];
    out += kHex[b & 0xF];
  }
  return out;
}

std::uint64_t to_ns(const eprosima::fastrtps::rtps::Time_t& time) {
  const std::int64_t ns = time.to_ns();
  return ns > 0 ? static_cast<std::uint64_t>(ns) : 0;
}





bool listed(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

void RecorderConfig::validate() const {
  if (output_path.empty()) throw ConfigError("record.output is empty: must name the .mcap file to write");
  for (const auto& name : allow) {
    if (find_catalog_topic(name) == nullptr) throw ConfigError("record.allow: '" + name + "' is not a sarloc topic");
  }
  for (const auto& name : block) {
    if (find_catalog_topic(name) == nullptr) throw ConfigError("record.block: '" + name + "' is not a sarloc topic");
  }
  auto positive = [](const char* field, double value, double low, double high) {
    if (!std::isfinite(value) || value < low || value > high) {
      throw ConfigError(std::string("record.") + field + " = " + config_value(value) + ": must be in [" +
                        config_value(low) + ", " + config_value(high) + "]");
    }
  };
  positive("flush_period_s", flush_period_s, 0.05, 60.0);
  positive("rotate_size_mb", rotate_size_mb, 0.0, 1e6);
  positive("rotate_duration_s", rotate_duration_s, 0.0, 1e7);
  positive("max_queue_mb", max_queue_mb, 1.0, 1e5);
  if (rotate_size_mb > 0.0 && rotate_size_mb < 0.1) {
    throw ConfigError("record.rotate_size_mb = " + config_value(rotate_size_mb) + ": must be 0 (never) or at least 0.1");
  }
}

struct Recorder::Channel {
  const CatalogTopic* topic = nullptr;
  recording::StringMap metadata;
  std::uint16_t file_channel = 0;  // its id in the current file
};

Recorder::Recorder(std::shared_ptr<Participant> participant, RecorderConfig config)
    : participant_(std::move(participant)), config_(std::move(config)) {
  config_.validate();
  std::vector<const CatalogTopic*> topics;
  for (const auto& topic : topic_catalog()) {
    if (!config_.allow.empty() && !listed(config_.allow, topic.name)) continue;
    if (listed(config_.block, topic.name)) continue;
    auto channel = std::make_unique<Channel>();
    channel->topic = &topic;
    counters_[topic.name];
    channels_.push_back(std::move(channel));
    topics.push_back(&topic);
  }
  // The file first: an unwritable path fails here, before any reader exists.
  recording::McapWriterOptions probe;
  probe.compression = config_.compression;
  probe.validate();
  { recording::McapWriter check(config_.output_path, probe); }
  files_.push_back(config_.output_path);

  RawReaderEvents events;
  events.on_sample = [this](std::size_t channel, RawSample&& sample, const fdds::SampleInfo& info) {
    Queued item;
    item.channel = channel;
    item.sequence = static_cast<std::uint32_t>(info.sample_identity.sequence_number().to64long());
    item.publish_time_ns = to_ns(info.source_timestamp);
    item.log_time_ns = to_ns(info.reception_timestamp);
    if (item.log_time_ns == 0) item.log_time_ns = static_cast<std::uint64_t>(MissionClock::wall_now_ns());
    for (std::size_t i = 0; i < item.participant.size(); ++i) item.participant[i] = info.publication_handle.value[i];
    item.bytes = std::move(sample.bytes);
    enqueue(std::move(item));
  };
  events.on_lost = [this](std::size_t channel, std::uint64_t count) { count_lost(channel, count); };
  events.on_rejected = [this](std::size_t channel, const std::string& reason) { count_rejected(channel, reason); };
  events.on_incompatible_qos = [this](std::size_t channel) { count_incompatible(channel); };
  readers_ = std::make_unique<RawTopicReaders>(participant_, topics, config_.partitions, std::move(events));
  std::string recorded_partitions = "(default)";
  for (const auto& name : config_.partitions) recorded_partitions += "," + name;
  for (std::size_t k = 0; k < channels_.size(); ++k) {
    auto& channel = *channels_[k];
    for (const auto& [key, value] : describe_qos(readers_->qos(k))) channel.metadata[key] = value;
    channel.metadata["qos_profile"] = channel.topic->profile + ".reader";
    channel.metadata["type"] = channel.topic->type_name;
    channel.metadata["partitions"] = recorded_partitions;
  }
  // Samples that arrived meanwhile wait in the queue.
  writer_thread_ = std::thread([this] { writer_loop(); });
}

Recorder::~Recorder() {
  try {
    close();
  } catch (const std::exception& error) {
    spdlog::error("recorder: {}", error.what());
  }
}

void Recorder::close() {
  if (closed_) return;
  closed_ = true;
  if (readers_) readers_->close();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (writer_thread_.joinable()) writer_thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  if (!error_.empty()) throw recording::RecordingError(error_);
}

void Recorder::enqueue(Queued item) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto& counters = counters_[channels_[item.channel]->topic->name];
  ++counters.received;
  if (!error_.empty()) {
    ++counters.rejected["recording_stopped"];
    return;
  }
  if (static_cast<double>(queued_bytes_ + item.bytes.size()) > config_.max_queue_mb * 1e6) {
    ++counters.rejected["queue_full"];
    return;
  }
  queued_bytes_ += item.bytes.size();
  queue_.push_back(std::move(item));
  wake_.notify_one();
}

void Recorder::count_lost(std::size_t channel, std::uint64_t count) {
  std::lock_guard<std::mutex> lock(mutex_);
  counters_[channels_[channel]->topic->name].lost += count;
}

void Recorder::count_rejected(std::size_t channel, const std::string& reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_[channels_[channel]->topic->name].rejected[reason];
}

void Recorder::count_incompatible(std::size_t channel) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_[channels_[channel]->topic->name].incompatible_qos;
  spdlog::warn("recorder: a writer of '{}' offers QoS the recorder cannot match", channels_[channel]->topic->name);
}

std::string Recorder::error() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_;
}

std::map<std::string, TopicCounters> Recorder::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

std::vector<std::string> Recorder::files() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return files_;
}

std::map<std::string, int> Recorder::matched_writers() const { return readers_->matched_writers(); }

std::string Recorder::next_file_path() {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::filesystem::path first(config_.output_path);
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, "-%03zu", files_.size());
  const std::string path = (first.parent_path() / (first.stem().string() + suffix + first.extension().string())).string();
  files_.push_back(path);
  return path;
}

void Recorder::writer_loop() {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(config_.flush_period_s));
  std::unique_ptr<recording::McapWriter> writer;
  std::uint16_t status_channel = 0;
  std::uint16_t events_channel = 0;
  std::set<std::pair<std::size_t, std::array<std::uint8_t, 12>>> writers_seen;  // per file
  Clock::time_point file_started;

  auto open = [&](const std::string& path) {
    recording::McapWriterOptions options;
    options.compression = config_.compression;
    options.sync_on_flush = config_.sync_on_flush;
    writer = std::make_unique<recording::McapWriter>(path, options);
    recording::StringMap metadata = config_.metadata;
    metadata["recorder_files_before"] = std::to_string(files().size() - 1);
    writer->write_metadata({"sarloc.recording", metadata});
    std::map<std::string, std::uint16_t> schemas;
    for (auto& channel : channels_) {
      const auto& topic = *channel->topic;
      if (!schemas.count(topic.type_name)) {
        schemas[topic.type_name] = writer->add_schema(topic.type_name, "omgidl", self_contained_idl(topic.idl_file));
      }
      channel->file_channel = writer->add_channel(topic.name, schemas[topic.type_name], "cdr", channel->metadata);
    }
    status_channel = writer->add_channel(kStatusTopic, 0, "json", {{"content", "recorder counters per topic, once per flush"}});
    events_channel = writer->add_channel(kEventsTopic, 0, "json",
                                         {{"content", "a participant's first sample on a topic (MCAP messages do not name their writer)"}});
    writers_seen.clear();
    writer->flush();
    file_started = Clock::now();
  };
  auto write_status = [&] {
    nlohmann::json status;
    for (const auto& [name, c] : counters()) {
      status["topics"][name] = {{"received", c.received}, {"written", c.written}, {"lost", c.lost},
                                {"rejected", c.rejected}, {"incompatible_qos", c.incompatible_qos}};
    }
    const std::string text = status.dump();
    const auto now = static_cast<std::uint64_t>(MissionClock::wall_now_ns());
    writer->write(status_channel, 0, now, now, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  };
  auto finish = [&] {
    write_status();
    recording::StringMap totals;
    for (const auto& [name, c] : counters()) {
      std::string rejected;
      for (const auto& [reason, n] : c.rejected) rejected += (rejected.empty() ? "" : ",") + reason + ":" + std::to_string(n);
      totals[name] = "received=" + std::to_string(c.received) + " written=" + std::to_string(c.written) +
                     " lost=" + std::to_string(c.lost) + " rejected=" + (rejected.empty() ? "0" : rejected);
    }
    writer->write_metadata({"sarloc.recorder_counters", totals});
    writer->close();
  };

  try {
    open(config_.output_path);
    auto next_flush = Clock::now() + period;
    while (true) {
      std::deque<Queued> batch;
      bool stopping = false;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait_until(lock, next_flush, [&] { return stopping_ || !queue_.empty(); });
        batch.swap(queue_);
        queued_bytes_ = 0;
        stopping = stopping_;
      }
      std::map<std::size_t, std::uint64_t> written;
      for (const auto& item : batch) {
        if (writers_seen.insert({item.channel, item.participant}).second) {
          const std::string event = nlohmann::json{{"event", "writer_seen"},
                                                   {"topic", channels_[item.channel]->topic->name},
                                                   {"participant", hex(item.participant)},
                                                   {"sequence", item.sequence},
                                                   {"log_time_ns", item.log_time_ns}}
                                        .dump();
          writer->write(events_channel, 0, item.log_time_ns, item.log_time_ns,
                        reinterpret_cast<const std::uint8_t*>(event.data()), event.size());
        }
        writer->write(channels_[item.channel]->file_channel, item.sequence, item.log_time_ns, item.publish_time_ns,
                      item.bytes.data(), item.bytes.size());
        ++written[item.channel];
      }
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& [channel, n] : written) counters_[channels_[channel]->topic->name].written += n;
      }
      if (stopping) break;
      if (Clock::now() >= next_flush) {
        write_status();
        writer->flush();
        next_flush = Clock::now() + period;
        const bool too_big = config_.rotate_size_mb > 0 && static_cast<double>(writer->bytes_written()) >= config_.rotate_size_mb * 1e6;
        const bool too_old = config_.rotate_duration_s > 0 &&
                             std::chrono::duration<double>(Clock::now() - file_started).count() >= config_.rotate_duration_s;
        if (too_big || too_old) {
          finish();
          open(next_file_path());
        }
      }
    }
    finish();
  } catch (const std::exception& error) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = error.what();
    queue_.clear();
    queued_bytes_ = 0;
    spdlog::error("recorder: recording stopped: {}", error_);
  }
}

std::string timestamped_recording_path(const std::string& directory, const std::string& prefix) {
  std::error_code ignored;
  std::filesystem::create_directories(directory, ignored);
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &utc);
  // A file name anyone can type: the mission's name with only letters, digits, '.', '_', '-'.
  std::string name = prefix;
  for (auto& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '-';
  }
  std::filesystem::path path = std::filesystem::path(directory) / (name + "-" + stamp + ".mcap");
  for (int n = 2; std::filesystem::exists(path); ++n) {
    path = std::filesystem::path(directory) / (name + "-" + stamp + "-" + std::to_string(n) + ".mcap");
  }
  return path.string();
}

}  // namespace sarloc::dds
