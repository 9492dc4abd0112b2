#pragma once
// A typed DataReader created from its topic's XML profile. The callback runs on a Fast DDS
// listener thread: it must only convert and enqueue (estimation runs on the node's own threads).
#include <atomic>
#include <chrono>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include "sarloc/dds/dds_error.hpp"
#include "sarloc/dds/endpoint_options.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/topics.hpp"

namespace sarloc::dds {

/// Optional callbacks besides data (all on the Fast DDS listener thread).
struct ReaderEvents {
  /// A matched writer became alive (true) or was lost: lease expired or writer gone (false).
  std::function<void(const eprosima::fastrtps::rtps::InstanceHandle_t&, bool)> on_liveliness;
  /// An instance was disposed or lost all its writers (info.instance_state tells which).
  std::function<void(const eprosima::fastdds::dds::SampleInfo&)> on_instance_gone;
};

namespace detail {

eprosima::fastdds::dds::Subscriber* create_subscriber(eprosima::fastdds::dds::DomainParticipant* participant,
                                                      const EndpointOptions& options);
/// Replaces the subscriber's partitions; throws DdsError naming `what` if Fast DDS refuses.
void set_partitions(eprosima::fastdds::dds::Subscriber* subscriber, const std::vector<std::string>& partitions,
                    const std::string& what);

template <class T>
class TypedReaderListener : public eprosima::fastdds::dds::DataReaderListener {
 public:
  using Callback = std::function<void(const T&, const eprosima::fastdds::dds::SampleInfo&)>;
  TypedReaderListener(Callback callback, ReaderEvents events)
      : callback_(std::move(callback)), events_(std::move(events)) {}

  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    T sample;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) {
        received.fetch_add(1);
        callback_(sample, info);
      } else if (events_.on_instance_gone) {
        events_.on_instance_gone(info);
      }
    }
  }
  void on_subscription_matched(eprosima::fastdds::dds::DataReader*,
                               const eprosima::fastdds::dds::SubscriptionMatchedStatus& status) override {
    matched.store(status.current_count);
  }
  void on_liveliness_changed(eprosima::fastdds::dds::DataReader*,
                             const eprosima::fastdds::dds::LivelinessChangedStatus& status) override {
    if (!events_.on_liveliness) return;
    // A crashed writer turns not-alive when its lease expires; a deleted one just leaves.
    if (status.alive_count_change > 0) events_.on_liveliness(status.last_publication_handle, true);
    if (status.alive_count_change < 0 || status.not_alive_count_change > 0) {
      events_.on_liveliness(status.last_publication_handle, false);
    }
  }

  std::atomic<int> matched{0};
  std::atomic<std::uint64_t> received{0};

 private:
  Callback callback_;
  ReaderEvents events_;
};

}  // namespace detail

template <class T>
class Reader {
 public:
  using Callback = typename detail::TypedReaderListener<T>::Callback;

  Reader(std::shared_ptr<Participant> participant, Callback callback, const EndpointOptions& options = {},
         ReaderEvents events = {})
      : participant_(std::move(participant)),
        listener_(std::make_unique<detail::TypedReaderListener<T>>(std::move(callback), std::move(events))) {
    using Traits = TopicTraits<T>;
    auto* topic = participant_->topic(Traits::kName, eprosima::fastdds::dds::TypeSupport(new typename Traits::PubSubType()));
    eprosima::fastdds::dds::TopicDescription* source = topic;
    if (options.admit_responder) source = participant_->filtered_by_responder(topic, options.admit_responder);
    subscriber_ = detail::create_subscriber(participant_->get(), options);
    const std::string profile =
        options.profile_override.empty() ? std::string(Traits::kProfile) + ".reader" : options.profile_override;
    reader_ = subscriber_->create_datareader_with_profile(source, profile, listener_.get());
    if (reader_ == nullptr) {
      participant_->get()->delete_subscriber(subscriber_);
      throw DdsError("cannot create reader for '" + std::string(Traits::kName) + "' from profile '" + profile + "'");
    }
  }

  ~Reader() {
    // Detach the listener first so no callback runs while we tear down.
    if (reader_ != nullptr) {
      reader_->set_listener(nullptr);
      subscriber_->delete_datareader(reader_);
    }
    if (subscriber_ != nullptr) participant_->get()->delete_subscriber(subscriber_);
  }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  int matched_writers() const { return listener_->matched.load(); }
  std::uint64_t received() const { return listener_->received.load(); }

  bool wait_for_writers(int count, std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (matched_writers() < count) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
  }

  /// Moves the reader to other DDS partitions (Writer::set_partitions). Throws DdsError if
  /// Fast DDS refuses.
  void set_partitions(const std::vector<std::string>& partitions) {
    detail::set_partitions(subscriber_, partitions, std::string("the '") + TopicTraits<T>::kName + "' reader");
  }

  eprosima::fastdds::dds::DataReader* get() const { return reader_; }

 private:
  std::shared_ptr<Participant> participant_;
  std::unique_ptr<detail::TypedReaderListener<T>> listener_;  // outlives reader_
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
};

}  // namespace sarloc::dds
