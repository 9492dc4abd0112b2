#include "sarloc/dds/speaker_claim.hpp"

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/identifier.hpp"
#include "sarloc/dds/raw_topic_type.hpp"

namespace sarloc::dds {

namespace {

using Speakers = WriterAuthority::Speakers;

template <class T>
std::optional<SpeakerClaim> decoded_claim(const std::vector<std::uint8_t>& bytes) {
  T sample;
  if (!decode_payload<typename TopicTraits<T>::PubSubType>(bytes, sample))
    throw InputError(std::string(TopicTraits<T>::kName) + ": a payload of " + std::to_string(bytes.size()) +
                     " bytes that does not decode");
  SpeakerClaim claim = speaker_claim(sample);
  check_identifier(claim.responder_id, std::string(TopicTraits<T>::kName) + " responder id");
  return claim;
}

template <class T>
bool is_topic(const std::string& topic) {
  return topic == TopicTraits<T>::kName;
}

}  // namespace

SpeakerClaim speaker_claim(const ::sarloc::FieldMeasurement& m) {
  return {m.rescuer_id().to_string(), Speakers::kDevice, "field measurement"};
}

SpeakerClaim speaker_claim(const ::sarloc::Odometry& o) {
  return {o.rescuer_id().to_string(), Speakers::kDevice, "odometry"};
}

SpeakerClaim speaker_claim(const ::sarloc::VictimEstimate& e) {
  return {e.rescuer_id().to_string(), Speakers::kDeviceOrCore, "victim estimate"};
}

SpeakerClaim speaker_claim(const ::sarloc::ResponderPosition& p) {
  // Map-aided fixes come from the core daemon; any other kind only from the device itself.
  if (p.source() == ::sarloc::POSITION_MAP_AIDED)
    return {p.responder_id().to_string(), Speakers::kDeviceOrCore, "map-aided position"};
  return {p.responder_id().to_string(), Speakers::kDevice, "responder position"};
}

SpeakerClaim speaker_claim(const ::sarloc::ResponderCandidates& c) {
  return {c.responder_id().to_string(), Speakers::kDeviceOrCore, "map-aided candidates"};
}

SpeakerClaim speaker_claim(const ::sarloc::ResponderAlarm& a) {
  return {a.responder_id().to_string(), Speakers::kDevice, "responder alarm"};
}

std::optional<SpeakerClaim> raw_speaker_claim(const std::string& topic, const std::vector<std::uint8_t>& bytes) {
  if (is_topic<::sarloc::FieldMeasurement>(topic)) return decoded_claim<::sarloc::FieldMeasurement>(bytes);
  if (is_topic<::sarloc::Odometry>(topic)) return decoded_claim<::sarloc::Odometry>(bytes);
  if (is_topic<::sarloc::VictimEstimate>(topic)) return decoded_claim<::sarloc::VictimEstimate>(bytes);
  if (is_topic<::sarloc::ResponderPosition>(topic)) return decoded_claim<::sarloc::ResponderPosition>(bytes);
  if (is_topic<::sarloc::ResponderCandidates>(topic)) return decoded_claim<::sarloc::ResponderCandidates>(bytes);
  if (is_topic<::sarloc::ResponderAlarm>(topic)) return decoded_claim<::sarloc::ResponderAlarm>(bytes);
  return std::nullopt;
}

std::string RawSampleAuthority::refusal(const std::string& topic, const std::vector<std::uint8_t>& bytes,
                                        const eprosima::fastrtps::rtps::InstanceHandle_t& writer) const {
  try {
    const std::optional<SpeakerClaim> claim = raw_speaker_claim(topic, bytes);
    if (!claim || admits(authority_, writer, *claim)) return {};
    return dds::refusal(authority_, writer, *claim);
  } catch (const InputError& e) {
    return e.what();
  }
}

}  // namespace sarloc::dds
