#pragma once
// Raw readers of several sarloc topics at once, for the tools that pass payloads on untouched
// (the recorder, the dashboard's Foxglove feed). Each topic is read with its own reader profile
// (so it matches what the topic's readers match: reliability, durability, EXCLUSIVE ownership)
// with a KEEP_LAST history of at least 1000 per instance (the listener takes every sample at
// once; KEEP_LAST never pushes back on a writer), in the default partition and in each of
// `partitions` ("*": every named one; DDS wildcards never match the default partition).
// Callbacks run on Fast DDS listener threads: they must be quick.
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/topic_catalog.hpp"

namespace sarloc::dds {

struct RawReaderEvents {
  /// A sample with its payload (indexes are positions in `topics`).
  std::function<void(std::size_t topic, RawSample&& sample, const eprosima::fastdds::dds::SampleInfo& info)> on_sample;
  std::function<void(std::size_t topic, std::uint64_t count)> on_lost;
  /// DDS refused a sample: "instances_limit", "samples_limit", "samples_per_instance_limit".
  std::function<void(std::size_t topic, const std::string& reason)> on_rejected;
  std::function<void(std::size_t topic)> on_incompatible_qos;
};

class RawTopicReaders {
 public:
  /// Throws DdsError when a reader cannot be created (none is left behind).
  RawTopicReaders(std::shared_ptr<Participant> participant, std::vector<const CatalogTopic*> topics,
                  std::vector<std::string> partitions, RawReaderEvents events);
  ~RawTopicReaders();
  RawTopicReaders(const RawTopicReaders&) = delete;
  RawTopicReaders& operator=(const RawTopicReaders&) = delete;

  const std::vector<const CatalogTopic*>& topics() const { return topics_; }
  /// The QoS topic `index` is read with (its default-partition reader).
  eprosima::fastdds::dds::DataReaderQos qos(std::size_t index) const;
  /// Writers matched per topic name.
  std::map<std::string, int> matched_writers() const;
  /// Deletes every reader now (no callback runs after it returns).
  void close();

 private:
  class Listener;
  struct Reading;
  std::shared_ptr<Participant> participant_;
  std::vector<const CatalogTopic*> topics_;
  RawReaderEvents events_;
  std::vector<std::unique_ptr<Reading>> readings_;  // one per topic
};

/// The minimum history the raw readers keep per instance.
inline constexpr std::int32_t kRawReaderDepth = 1000;

/// A reader's QoS as text, for a recording's channel metadata.
std::map<std::string, std::string> describe_qos(const eprosima::fastdds::dds::DataReaderQos& qos);

}  // namespace sarloc::dds
