#pragma once
// Every sarloc topic as data, for the tools that handle all of them alike without knowing
// their types at compile time: the recorder, the replayer and the report. topics.hpp is the
// typed version the nodes use; both list the same topics (a test checks it).
#include <fastdds/dds/topic/TopicDataType.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace sarloc::dds {

struct CatalogTopic {
  std::string name;       ///< on the wire, e.g. "sarloc/odometry"
  std::string profile;    ///< QoS profiles "<profile>.writer" / "<profile>.reader" in topics.xml
  std::string type_name;  ///< scoped IDL type name, e.g. "sarloc::Odometry"
  std::string idl_file;   ///< the IDL file that defines the type
  /// A new instance of the generated PubSubType (owned by the caller).
  std::function<std::unique_ptr<eprosima::fastdds::dds::TopicDataType>()> make_type;
};

const std::vector<CatalogTopic>& topic_catalog();
/// nullptr when `name` is not a sarloc topic.
const CatalogTopic* find_catalog_topic(const std::string& name);

}  // namespace sarloc::dds
