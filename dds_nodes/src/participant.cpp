#include "sarloc/dds/participant.hpp"

#include <spdlog/spdlog.h>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <filesystem>
#include <set>

#include "sarloc/core/common/validate.hpp"
#include "sarloc/dds/dds_error.hpp"
#include "sarloc/dds/security_check.hpp"

namespace sarloc::dds {

using eprosima::fastdds::dds::DomainParticipantFactory;
using eprosima::fastdds::dds::DomainParticipantQos;
using eprosima::fastrtps::types::ReturnCode_t;

void ParticipantConfig::validate() const {
  if (profiles_file.empty()) throw ConfigError("dds.profiles_file is empty: must name a Fast DDS XML file");
  if (!std::filesystem::is_regular_file(profiles_file)) {
    throw ConfigError("dds.profiles_file = '" + profiles_file + "': no such file");
  }
  if (!std::filesystem::is_regular_file(topics_file)) {
    throw ConfigError("dds.topics_file = '" + topics_file + "': no such file");
  }
  if (profile.empty()) throw ConfigError("dds.profile is empty: must name a participant profile");
  if (domain_id > 232) {
    throw ConfigError("dds.domain_id = " + config_value(domain_id) + ": must be <= 232 (Fast DDS port mapping)");
  }
  if (name.empty()) throw ConfigError("dds.name is empty");
}

void load_profiles_file(const std::string& path) {
  static std::mutex mutex;
  static std::set<std::string> loaded;
  std::lock_guard<std::mutex> lock(mutex);
  const std::string canonical = std::filesystem::weakly_canonical(path).string();
  if (loaded.count(canonical) != 0) return;
  if (DomainParticipantFactory::get_instance()->load_XML_profiles_file(canonical) != ReturnCode_t::RETCODE_OK) {
    throw DdsError("cannot load Fast DDS XML profiles from '" + canonical + "'");
  }
  loaded.insert(canonical);
}

Participant::Participant(const ParticipantConfig& config) : config_(config) {
  config_.validate();
  load_profiles_file(config_.profiles_file);
  load_profiles_file(config_.topics_file);

  // Start from the profile itself; only the name is ours (the profile's transports,
  // locators and discovery settings all stay as written in the XML).
  auto* factory = DomainParticipantFactory::get_instance();
  DomainParticipantQos qos;
  if (factory->get_participant_qos_from_profile(config_.profile, qos) != ReturnCode_t::RETCODE_OK) {
    throw DdsError("participant profile '" + config_.profile + "' not found in '" + config_.profiles_file + "'");
  }
  qos.name(config_.name);
  secured_ = check_security(qos, config_.profile, config_.require_security, config_.allow_unauthenticated);
  participant_ = factory->create_participant(static_cast<eprosima::fastdds::dds::DomainId_t>(config_.domain_id), qos);
  if (participant_ == nullptr) {
    throw DdsError("cannot create DDS participant '" + config_.name + "' on domain " +
                   std::to_string(config_.domain_id) + " from profile '" + config_.profile + "'");
  }
  spdlog::info("participant '{}' on domain {}, profile {}: DDS Security: {}", config_.name, config_.domain_id,
               config_.profile, secured_ ? "on (authenticated, encrypted)" : "off");
}

Participant::~Participant() {
  // Writers and readers hold shared_ptrs to us, so only topics are left here.
  for (auto* filtered : filtered_) participant_->delete_contentfilteredtopic(filtered);
  for (auto& [name, topic] : topics_) participant_->delete_topic(topic);
  if (responder_filters_) participant_->unregister_content_filter_factory(kResponderFilterClass);
  participant_->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

bool Participant::is_own_writer(const eprosima::fastrtps::rtps::InstanceHandle_t& publication_handle) const {
  const auto& prefix = participant_->guid().guidPrefix;
  for (std::size_t i = 0; i < eprosima::fastrtps::rtps::GuidPrefix_t::size; ++i) {
    if (prefix.value[i] != publication_handle.value[i]) return false;
  }
  return true;
}

std::string handle_text(const eprosima::fastrtps::rtps::InstanceHandle_t& handle) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < 16; ++i) {
    out += kHex[(handle.value[i] >> 4) & 0xF];
    out += kHex[handle.value[i] & 0xF];
  }
  return out;
}

eprosima::fastdds::dds::Topic* Participant::topic(const std::string& name,
                                                  eprosima::fastdds::dds::TypeSupport type) {
  std::lock_guard<std::mutex> lock(topics_mutex_);
  // One topic, one way of (de)serializing: a raw reader on a topic created with the generated
  // type (or the reverse) would read one kind of sample into the other.
  const std::type_index kind(typeid(*type.get()));
  if (auto it = topics_.find(name); it != topics_.end()) {
    if (topic_kinds_.at(name) != kind) {
      throw DdsError("topic '" + name + "' already exists in this participant with another type support (raw and typed endpoints need participants of their own)");
    }
    return it->second;
  }
  const std::string type_name = type.get_type_name();
  if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK) {
    throw DdsError("cannot register type '" + type_name + "' for topic '" + name + "'");
  }
  auto* topic = participant_->create_topic(name, type_name, eprosima::fastdds::dds::TOPIC_QOS_DEFAULT);
  if (topic == nullptr) throw DdsError("cannot create topic '" + name + "' of type '" + type_name + "'");
  topics_.emplace(name, topic);
  topic_kinds_.emplace(name, kind);
  return topic;
}

eprosima::fastdds::dds::TopicDescription* Participant::filtered_by_responder(eprosima::fastdds::dds::Topic* topic,
                                                                             ResponderPredicate admit) {
  std::lock_guard<std::mutex> lock(topics_mutex_);
  if (!responder_filters_) {
    auto factory = std::make_unique<ResponderFilterFactory>();
    if (participant_->register_content_filter_factory(kResponderFilterClass, factory.get()) != ReturnCode_t::RETCODE_OK) {
      throw DdsError("cannot register the content filter class " + std::string(kResponderFilterClass));
    }
    responder_filters_ = std::move(factory);
  }
  const std::string name = topic->get_name() + "/admitted-" + std::to_string(filtered_.size());
  auto* cft = participant_->create_contentfilteredtopic(name, topic, responder_filters_->expression_for(std::move(admit)),
                                                        {}, kResponderFilterClass);
  if (cft == nullptr) throw DdsError("cannot filter topic '" + topic->get_name() + "' by responder");
  filtered_.push_back(cft);
  return cft;
}

}  // namespace sarloc::dds
