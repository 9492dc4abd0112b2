#include "sarloc/dds/topic_catalog.hpp"

#include "sarloc/dds/topics.hpp"

namespace sarloc::dds {

namespace {

template <class T>
CatalogTopic entry(const char* idl_file) {
  using Traits = TopicTraits<T>;
  CatalogTopic topic;
  topic.name = Traits::kName;
  topic.profile = Traits::kProfile;
  topic.type_name = typename Traits::PubSubType().getName();
  topic.idl_file = idl_file;
  topic.make_type = [] { return std::unique_ptr<eprosima::fastdds::dds::TopicDataType>(new typename Traits::PubSubType()); };
  return topic;
}

}  // namespace

const std::vector<CatalogTopic>& topic_catalog() {
  static const std::vector<CatalogTopic> catalog = {
      entry<FieldMeasurement>("avalanche.idl"), entry<Odometry>("responder.idl"),
      entry<VictimEstimate>("responder.idl"),   entry<Guidance>("responder.idl"),
      entry<ResponderPosition>("incident.idl"), entry<ResponderCandidates>("incident.idl"),
      entry<IncidentFrame>("common.idl"),       entry<FusedVictim>("incident.idl"),
      entry<TeamStatus>("incident.idl"),        entry<IncidentSummary>("incident.idl"),
      entry<SearchPlan>("incident.idl"),        entry<ResponderAlarm>("incident.idl"),
      entry<IncidentAlarm>("incident.idl"),     entry<AlarmAcknowledgement>("incident.idl"),
      entry<VictimRecovery>("incident.idl"),    entry<DigOrder>("incident.idl"),
      entry<DepositDrawing>("incident.idl"),    entry<RescuerHandover>("handover.idl"),
      entry<NodeStatus>("status.idl"),
  };
  return catalog;
}

const CatalogTopic* find_catalog_topic(const std::string& name) {
  for (const auto& topic : topic_catalog()) {
    if (topic.name == name) return &topic;
  }
  return nullptr;
}

}  // namespace sarloc::dds
