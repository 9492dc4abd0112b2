#pragma once
// One DDS participant per process, created from a Fast DDS XML profile.
//
// Profiles only apply when the participant is created from them (NOTES: code that builds its
// own DomainParticipantQos silently ignores the XML), so this is the only place sarloc creates
// participants, and it always starts from the named profile.
//
//   ParticipantConfig cfg;                 // defaults: config/dds/localhost.xml, domain 0
//   cfg.domain_id = 17;
//   Participant participant(cfg);
//   Writer<sarloc::FieldMeasurement> writer(participant);
//   Reader<responder::VictimEstimate> reader(participant, [](const auto& sample, const auto& info) {...});
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/topic/ContentFilteredTopic.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <typeindex>
#include <vector>

#include "sarloc/dds/install_layout.hpp"
#include "sarloc/dds/responder_filter.hpp"

namespace sarloc::dds {

struct ParticipantConfig {
  /// Fast DDS XML file with the participant profile (localhost.xml, lan.xml, discovery-client.xml).
  std::string profiles_file = dds_config_dir() + "/localhost.xml";
  /// Participant profile name inside profiles_file.
  std::string profile = "sarloc_localhost";
  /// Per-topic writer/reader QoS profiles ("<topic>.writer" / "<topic>.reader").
  std::string topics_file = dds_config_dir() + "/topics.xml";
  /// DDS domain; Fast DDS maps it to UDP ports, so at most 232.
  std::uint32_t domain_id = 0;
  /// Participant name seen by discovery tools (fastdds discovery, monitor).
  std::string name = "sarloc";
  /// Refuse to start unless the profile enables DDS Security (deploy/security/). Whatever this
  /// says, a profile that sets any dds.sec.* property must set all of them correctly.
  bool require_security = false;
  /// A profile that reaches beyond this machine runs without DDS Security only when this says
  /// so (a drill on a closed network); on loopback-only profiles it changes nothing.
  bool allow_unauthenticated = false;
  /// The mission's core daemons (node ids): under DDS Security their identities may write
  /// estimates and map-aided positions for any responder (writer_authority.hpp). Filled from
  /// the mission file, not a key of its own.
  std::vector<std::string> core_node_ids;

  /// Throws ConfigError naming the field, the value and the rule.
  void validate() const;
};

/// Owns the DomainParticipant and its topics; writers and readers keep it alive.
class Participant {
 public:
  explicit Participant(const ParticipantConfig& config);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  eprosima::fastdds::dds::DomainParticipant* get() const { return participant_; }
  const ParticipantConfig& config() const { return config_; }
  /// True when the participant runs with DDS Security (checked at start-up).
  bool secured() const { return secured_; }

  /// True when `publication_handle` (SampleInfo) is a writer of this participant: a reader
  /// also receives what its own participant writes.
  bool is_own_writer(const eprosima::fastrtps::rtps::InstanceHandle_t& publication_handle) const;

  /// The topic `name` of type `type` (registered and created once, then shared).
  eprosima::fastdds::dds::Topic* topic(const std::string& name, eprosima::fastdds::dds::TypeSupport type);
  /// `topic` with only the samples whose responder `admit` accepts (a ContentFilteredTopic of
  /// the responder_filter.hpp class, one per call).
  eprosima::fastdds::dds::TopicDescription* filtered_by_responder(eprosima::fastdds::dds::Topic* topic,
                                                                  ResponderPredicate admit);

 private:
  ParticipantConfig config_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  bool secured_ = false;
  std::mutex topics_mutex_;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  std::map<std::string, std::type_index> topic_kinds_;  // the TopicDataType class of each topic
  std::unique_ptr<ResponderFilterFactory> responder_filters_;  // registered on first use
  std::vector<eprosima::fastdds::dds::ContentFilteredTopic*> filtered_;
};

/// A writer's GUID (a SampleInfo's publication_handle) as 32 hex digits: the first 24 name
/// its participant.
std::string handle_text(const eprosima::fastrtps::rtps::InstanceHandle_t& handle);

/// Loads a Fast DDS XML profile file once per process (throws DdsError naming the file).
void load_profiles_file(const std::string& path);

}  // namespace sarloc::dds
