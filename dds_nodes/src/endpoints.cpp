#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/qos/PublisherQos.hpp>
#include <fastdds/dds/subscriber/qos/SubscriberQos.hpp>

#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"

namespace sarloc::dds::detail {

// Partitions live in Publisher/Subscriber QoS in DDS, so every endpoint gets its own
// publisher/subscriber: cheap, and sectors can differ per endpoint.
eprosima::fastdds::dds::Publisher* create_publisher(eprosima::fastdds::dds::DomainParticipant* participant,
                                                    const EndpointOptions& options) {
  eprosima::fastdds::dds::PublisherQos qos = participant->get_default_publisher_qos();
  for (const auto& name : options.partitions) qos.partition().push_back(name.c_str());
  auto* publisher = participant->create_publisher(qos);
  if (publisher == nullptr) throw DdsError("cannot create DDS publisher");
  return publisher;
}

eprosima::fastdds::dds::Subscriber* create_subscriber(eprosima::fastdds::dds::DomainParticipant* participant,
                                                      const EndpointOptions& options) {
  eprosima::fastdds::dds::SubscriberQos qos = participant->get_default_subscriber_qos();
  for (const auto& name : options.partitions) qos.partition().push_back(name.c_str());
  auto* subscriber = participant->create_subscriber(qos);
  if (subscriber == nullptr) throw DdsError("cannot create DDS subscriber");
  return subscriber;
}

namespace {

// Publisher and Subscriber alike: the partition policy is mutable.
template <class Entity, class Qos>
void replace_partitions(Entity* entity, const std::vector<std::string>& partitions, const std::string& what) {
  Qos qos;
  entity->get_qos(qos);
  qos.partition().clear();
  for (const auto& name : partitions) qos.partition().push_back(name.c_str());
  if (entity->set_qos(qos) != eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
    throw DdsError("cannot move " + what + " to other partitions");
  }
}

}  // namespace

void set_partitions(eprosima::fastdds::dds::Publisher* publisher, const std::vector<std::string>& partitions,
                    const std::string& what) {
  replace_partitions<eprosima::fastdds::dds::Publisher, eprosima::fastdds::dds::PublisherQos>(publisher, partitions,
                                                                                              what);
}

void set_partitions(eprosima::fastdds::dds::Subscriber* subscriber, const std::vector<std::string>& partitions,
                    const std::string& what) {
  replace_partitions<eprosima::fastdds::dds::Subscriber, eprosima::fastdds::dds::SubscriberQos>(subscriber, partitions,
                                                                                                what);
}

}  // namespace sarloc::dds::detail
