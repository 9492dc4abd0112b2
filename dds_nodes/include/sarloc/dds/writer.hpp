#pragma once
// A typed DataWriter created from its topic's XML profile, deleted with its publisher.
#include <atomic>
#include <chrono>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/publisher/qos/PublisherQos.hpp>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "sarloc/dds/dds_error.hpp"
#include "sarloc/dds/endpoint_options.hpp"
#include "sarloc/dds/participant.hpp"
#include "sarloc/dds/topics.hpp"

namespace sarloc::dds {

namespace detail {

// Always attached: a writer with a deadline and no listener can crash in Fast DDS 2.9 (NOTES).
class CountingWriterListener : public eprosima::fastdds::dds::DataWriterListener {
 public:
  void on_publication_matched(eprosima::fastdds::dds::DataWriter*,
                              const eprosima::fastdds::dds::PublicationMatchedStatus& status) override {
    matched.store(status.current_count);
  }
  void on_offered_deadline_missed(eprosima::fastdds::dds::DataWriter*,
                                  const eprosima::fastdds::dds::OfferedDeadlineMissedStatus&) override {
    deadlines_missed.fetch_add(1);
  }
  std::atomic<int> matched{0};
  std::atomic<std::uint64_t> deadlines_missed{0};
};

eprosima::fastdds::dds::Publisher* create_publisher(eprosima::fastdds::dds::DomainParticipant* participant,
                                                    const EndpointOptions& options);
/// Replaces the publisher's partitions; throws DdsError naming `what` if Fast DDS refuses.
void set_partitions(eprosima::fastdds::dds::Publisher* publisher, const std::vector<std::string>& partitions,
                    const std::string& what);

}  // namespace detail

template <class T>
class Writer {
 public:
  explicit Writer(std::shared_ptr<Participant> participant, const EndpointOptions& options = {})
      : participant_(std::move(participant)), listener_(std::make_unique<detail::CountingWriterListener>()) {
    using Traits = TopicTraits<T>;
    auto* topic = participant_->topic(Traits::kName, eprosima::fastdds::dds::TypeSupport(new typename Traits::PubSubType()));
    publisher_ = detail::create_publisher(participant_->get(), options);
    const std::string profile =
        options.profile_override.empty() ? std::string(Traits::kProfile) + ".writer" : options.profile_override;
    writer_ = publisher_->create_datawriter_with_profile(topic, profile, listener_.get());
    if (writer_ == nullptr) {
      participant_->get()->delete_publisher(publisher_);
      throw DdsError("cannot create writer for '" + std::string(Traits::kName) + "' from profile '" + profile + "'");
    }
  }

  ~Writer() {
    if (writer_ != nullptr) publisher_->delete_datawriter(writer_);
    if (publisher_ != nullptr) participant_->get()->delete_publisher(publisher_);
  }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// RETCODE_OK, or why DDS refused the sample (return_code_name). Fast DDS 2.9 says
  /// RETCODE_TIMEOUT for any sample its history refuses, a full max_instances included.
  eprosima::fastrtps::types::ReturnCode_t write_returning(const T& sample) {
    return writer_->write(const_cast<T*>(&sample), eprosima::fastrtps::rtps::c_InstanceHandle_Unknown);
  }
  /// False when DDS refused the sample (write_returning says why).
  bool write(const T& sample) { return write_returning(sample) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK; }

  /// Disposes the instance whose key fields `key_holder` carries. Fast DDS disposes only an
  /// instance its writer registered, so it is registered first: a writer that took over may
  /// dispose of what its predecessor wrote (a no-op when it wrote the instance itself).
  bool dispose(const T& key_holder) {
    auto* data = const_cast<T*>(&key_holder);
    const auto handle = writer_->register_instance(data);
    if (handle == eprosima::fastrtps::rtps::InstanceHandle_t()) return false;
    return writer_->dispose(data, handle) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }

  /// Ownership strength on an EXCLUSIVE topic, changed at run time (the DDS policy is
  /// mutable; Fast DDS 2.9 re-announces it and readers honour it: QosBehaviour tests).
  /// Throws DdsError if Fast DDS refuses.
  void set_ownership_strength(std::uint32_t strength) {
    eprosima::fastdds::dds::DataWriterQos qos;
    writer_->get_qos(qos);
    qos.ownership_strength().value = strength;
    if (writer_->set_qos(qos) != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
      throw DdsError("cannot set the ownership strength of the '" + std::string(TopicTraits<T>::kName) +
                     "' writer to " + std::to_string(strength));
    }
  }

  /// Moves the writer to other DDS partitions (a sector's, as a device walks into it): the
  /// policy is mutable, and readers match or unmatch as their partitions say. Throws DdsError
  /// if Fast DDS refuses.
  void set_partitions(const std::vector<std::string>& partitions) {
    detail::set_partitions(publisher_, partitions, std::string("the '") + TopicTraits<T>::kName + "' writer");
  }
  /// Asserts a MANUAL_BY_TOPIC writer's liveliness without writing.
  bool assert_liveliness() {
    return writer_->assert_liveliness() == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }

  int matched_readers() const { return listener_->matched.load(); }

  /// Waits until every matched reader acknowledged what was written; false on timeout.
  bool wait_for_acknowledgments(std::chrono::milliseconds timeout) {
    return writer_->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(static_cast<double>(timeout.count()) / 1e3)) ==
           eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }

  /// Waits until at least `count` readers matched; false on timeout.
  bool wait_for_readers(int count, std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (matched_readers() < count) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
  }

  eprosima::fastdds::dds::DataWriter* get() const { return writer_; }

 private:
  std::shared_ptr<Participant> participant_;
  std::unique_ptr<detail::CountingWriterListener> listener_;  // outlives writer_
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

}  // namespace sarloc::dds
