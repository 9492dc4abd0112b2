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

}  // namespace sarloc::dds::detail
