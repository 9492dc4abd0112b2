#include "sarloc/dds/raw_topic_readers.hpp"

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include "sarloc/dds/dds_error.hpp"

namespace sarloc::dds {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

class RawTopicReaders::Listener : public fdds::DataReaderListener {
 public:
  Listener(const RawReaderEvents& events, std::size_t topic) : events_(events), topic_(topic) {}

  void on_data_available(fdds::DataReader* reader) override {
    RawSample sample;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;  // dispose/unregister notices carry no payload
      if (events_.on_sample) events_.on_sample(topic_, std::move(sample), info);
    }
  }
  void on_sample_lost(fdds::DataReader*, const fdds::SampleLostStatus& status) override {
    if (status.total_count_change > 0 && events_.on_lost) events_.on_lost(topic_, static_cast<std::uint64_t>(status.total_count_change));
  }
  void on_sample_rejected(fdds::DataReader*, const fdds::SampleRejectedStatus& status) override {
    static const char* const reasons[] = {"not_rejected", "instances_limit", "samples_limit", "samples_per_instance_limit"};
    const auto kind = static_cast<std::size_t>(status.last_reason);
    if (!events_.on_rejected) return;
    for (std::uint32_t i = 0; i < status.total_count_change; ++i) events_.on_rejected(topic_, kind < 4 ? reasons[kind] : "other");
  }
  void on_requested_incompatible_qos(fdds::DataReader*, const fdds::RequestedIncompatibleQosStatus&) override {
    if (events_.on_incompatible_qos) events_.on_incompatible_qos(topic_);
  }

 private:
  const RawReaderEvents& events_;
  std::size_t topic_;
};

struct RawTopicReaders::Reading {
  fdds::Topic* topic = nullptr;
  std::unique_ptr<Listener> listener;
  std::vector<std::pair<fdds::Subscriber*, fdds::DataReader*>> readers;  // default partition first
};

RawTopicReaders::RawTopicReaders(std::shared_ptr<Participant> participant, std::vector<const CatalogTopic*> topics,
                                 std::vector<std::string> partitions, RawReaderEvents events)
    : participant_(std::move(participant)), topics_(std::move(topics)), events_(std::move(events)) {
  std::vector<std::vector<std::string>> partition_sets = {{}};
  for (const auto& name : partitions) partition_sets.push_back({name});
  try {
    for (std::size_t k = 0; k < topics_.size(); ++k) {
      const CatalogTopic& catalog = *topics_[k];
      auto reading = std::make_unique<Reading>();
      reading->listener = std::make_unique<Listener>(events_, k);
      reading->topic = participant_->topic(catalog.name, fdds::TypeSupport(new RawPubSubType(catalog.make_type())));
      readings_.push_back(std::move(reading));
      auto& r = *readings_.back();
      for (const auto& set : partition_sets) {
        fdds::SubscriberQos subscriber_qos = participant_->get()->get_default_subscriber_qos();
        for (const auto& name : set) subscriber_qos.partition().push_back(name.c_str());
        auto* subscriber = participant_->get()->create_subscriber(subscriber_qos);
        if (subscriber == nullptr) throw DdsError("cannot create a subscriber for '" + catalog.name + "'");
        fdds::DataReaderQos qos;
        const std::string profile = catalog.profile + ".reader";
        if (subscriber->get_datareader_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK) {
          participant_->get()->delete_subscriber(subscriber);
          throw DdsError("no reader profile '" + profile + "' in the topics file");
        }
        qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        qos.history().depth = std::max(qos.history().depth, kRawReaderDepth);
        qos.resource_limits().max_samples_per_instance = qos.history().depth;
        qos.resource_limits().max_samples = 0;  // unlimited
        auto* reader = subscriber->create_datareader(r.topic, qos, r.listener.get());
        if (reader == nullptr) {
          participant_->get()->delete_subscriber(subscriber);
          throw DdsError("cannot create a raw reader of '" + catalog.name + "'");
        }
        r.readers.emplace_back(subscriber, reader);
      }
    }
  } catch (...) {
    close();
    throw;
  }
}

RawTopicReaders::~RawTopicReaders() { close(); }

void RawTopicReaders::close() {
  for (auto& r : readings_) {
    for (auto& [subscriber, reader] : r->readers) {
      reader->set_listener(nullptr);
      subscriber->delete_datareader(reader);
      participant_->get()->delete_subscriber(subscriber);
    }
    r->readers.clear();
  }
}

fdds::DataReaderQos RawTopicReaders::qos(std::size_t index) const {
  const auto& readers = readings_.at(index)->readers;
  return readers.empty() ? fdds::DataReaderQos{} : readers.front().second->get_qos();
}

std::map<std::string, int> RawTopicReaders::matched_writers() const {
  std::map<std::string, int> matched;
  for (std::size_t k = 0; k < readings_.size(); ++k) {
    int count = 0;
    for (const auto& [subscriber, reader] : readings_[k]->readers) {
      fdds::SubscriptionMatchedStatus status;
      if (reader->get_subscription_matched_status(status) == ReturnCode_t::RETCODE_OK) count += status.current_count;
    }
    matched[topics_[k]->name] = count;
  }
  return matched;
}

std::map<std::string, std::string> describe_qos(const fdds::DataReaderQos& qos) {
  auto durability = [&] {
    switch (qos.durability().kind) {
      case fdds::VOLATILE_DURABILITY_QOS: return "VOLATILE";
      case fdds::TRANSIENT_LOCAL_DURABILITY_QOS: return "TRANSIENT_LOCAL";
      case fdds::TRANSIENT_DURABILITY_QOS: return "TRANSIENT";
      case fdds::PERSISTENT_DURABILITY_QOS: return "PERSISTENT";
    }
    return "?";
  };
  auto liveliness = [&] {
    switch (qos.liveliness().kind) {
      case fdds::AUTOMATIC_LIVELINESS_QOS: return "AUTOMATIC";
      case fdds::MANUAL_BY_PARTICIPANT_LIVELINESS_QOS: return "MANUAL_BY_PARTICIPANT";
      case fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS: return "MANUAL_BY_TOPIC";
    }
    return "?";
  };
  return {{"reliability", qos.reliability().kind == fdds::RELIABLE_RELIABILITY_QOS ? "RELIABLE" : "BEST_EFFORT"},
          {"durability", durability()},
          {"liveliness", liveliness()},
          {"ownership", qos.ownership().kind == fdds::EXCLUSIVE_OWNERSHIP_QOS ? "EXCLUSIVE" : "SHARED"},
          {"recorder_history_depth", std::to_string(qos.history().depth)}};
}

}  // namespace sarloc::dds
