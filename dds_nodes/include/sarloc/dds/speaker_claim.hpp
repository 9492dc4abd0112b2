#pragma once
// Whom a sample speaks for, and so who may write it (WriterAuthority): one rule per topic, used by
// every typed reader that checks its writer and by the dashboard's raw Foxglove feed, which
// relays payloads it never decodes otherwise (issue 59: under DDS Security a stolen device's
// mayday "for r1" reached a Foxglove viewer although the picture refused it).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/dds/topics.hpp"
#include "sarloc/dds/writer_authority.hpp"

namespace sarloc::dds {

struct SpeakerClaim {
  std::string responder_id;
  WriterAuthority::Speakers speakers = WriterAuthority::Speakers::kDevice;
  const char* what = "";  ///< "odometry": names the sample in a refusal's log line
};

// Sensor samples and alarms only from the responder's device; estimates and map-aided
// positions from it or a core daemon (WriterAuthority::Speakers).
SpeakerClaim speaker_claim(const ::sarloc::FieldMeasurement& m);
SpeakerClaim speaker_claim(const ::sarloc::Odometry& o);
SpeakerClaim speaker_claim(const ::sarloc::VictimEstimate& e);
SpeakerClaim speaker_claim(const ::sarloc::ResponderPosition& p);
SpeakerClaim speaker_claim(const ::sarloc::ResponderCandidates& c);
SpeakerClaim speaker_claim(const ::sarloc::ResponderAlarm& a);

/// The claim of one serialized payload of the sarloc topic `topic` (RawTopicReaders). nullopt
/// for a topic whose samples speak for no responder (its DDS Security grant is its check).
/// Throws InputError when the payload of a responder's topic does not decode or its id is not
/// an identifier: such a sample is refused, not relayed.
std::optional<SpeakerClaim> raw_speaker_claim(const std::string& topic, const std::vector<std::uint8_t>& bytes);

/// authority.admits for the claim.
inline bool admits(const WriterAuthority& authority, const eprosima::fastrtps::rtps::InstanceHandle_t& writer,
                   const SpeakerClaim& claim) {
  return authority.admits(writer, claim.responder_id, claim.speakers);
}
/// authority.refusal's log line for a claim it did not admit.
inline std::string refusal(const WriterAuthority& authority, const eprosima::fastrtps::rtps::InstanceHandle_t& writer,
                           const SpeakerClaim& claim) {
  return authority.refusal(claim.what, writer, claim.responder_id);
}

/// The check of a raw relay (the dashboard's Foxglove feed): a payload of a responder's topic
/// passes only when its writer may speak for the responder it names, as in the picture, and one
/// that does not decode never passes. Without DDS Security every decodable payload passes.
class RawSampleAuthority {
 public:
  explicit RawSampleAuthority(std::shared_ptr<const Participant> participant) : authority_(std::move(participant)) {}
  /// Empty when the payload may be relayed; otherwise why not, for the log.
  std::string refusal(const std::string& topic, const std::vector<std::uint8_t>& bytes,
                      const eprosima::fastrtps::rtps::InstanceHandle_t& writer) const;

 private:
  WriterAuthority authority_;
};

}  // namespace sarloc::dds
