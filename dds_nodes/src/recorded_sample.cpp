#include "sarloc/dds/recorded_sample.hpp"

#include <functional>
#include <map>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/topics.hpp"

namespace sarloc::dds {

namespace {

template <class Idl>
Idl decode_idl(const std::vector<std::uint8_t>& bytes) {
  Idl sample;
  if (!decode_payload<typename TopicTraits<Idl>::PubSubType>(bytes, sample)) {
    throw InputError(std::string(TopicTraits<Idl>::kName) + ": the recorded sample does not decode");
  }
  return sample;
}

using Decoder = std::function<RecordedSample(const std::vector<std::uint8_t>&)>;

template <class Idl>
std::pair<const std::string, Decoder> converted() {
  return {TopicTraits<Idl>::kName,
          [](const std::vector<std::uint8_t>& b) { return RecordedSample(to_core(decode_idl<Idl>(b))); }};
}

template <class Idl>
std::pair<const std::string, Decoder> as_generated() {
  return {TopicTraits<Idl>::kName,
          [](const std::vector<std::uint8_t>& b) { return RecordedSample(decode_idl<Idl>(b)); }};
}

const std::map<std::string, Decoder>& decoders() {
  static const std::map<std::string, Decoder> table{
      converted<::sarloc::FieldMeasurement>(),    converted<::sarloc::Odometry>(),
      converted<::sarloc::VictimEstimate>(),      converted<::sarloc::Guidance>(),
      converted<::sarloc::ResponderAlarm>(),      converted<::sarloc::ResponderPosition>(),
      converted<::sarloc::ResponderCandidates>(), converted<::sarloc::FusedVictim>(),
      converted<::sarloc::TeamStatus>(),          converted<::sarloc::IncidentAlarm>(),
      converted<::sarloc::IncidentFrame>(),       converted<::sarloc::SearchPlan>(),
      as_generated<::sarloc::NodeStatus>(),       as_generated<::sarloc::VictimRecovery>()};
  return table;
}

}  // namespace

std::optional<RecordedSample> decode_recorded(const std::string& topic, const std::vector<std::uint8_t>& bytes) {
  const auto it = decoders().find(topic);
  if (it == decoders().end()) return std::nullopt;
  return it->second(bytes);
}

}  // namespace sarloc::dds
