// Whom a sample speaks for (speaker_claim.hpp): the one rule of who may write it, typed and raw.
// The raw form is what the dashboard's Foxglove feed checks before it relays a payload.
#include "sarloc/dds/speaker_claim.hpp"

#include <gtest/gtest.h>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/dds/raw_topic_type.hpp"

namespace sarloc::dds {
namespace {

using Speakers = WriterAuthority::Speakers;

template <class T>
std::vector<std::uint8_t> payload(const T& sample) {
  return encode_payload<typename TopicTraits<T>::PubSubType>(sample);
}

TEST(SpeakerClaim, SensorSamplesAndAlarmsOnlyFromTheDeviceEstimatesAndMapAidedFixesAlsoFromACore) {
  ::sarloc::FieldMeasurement m;
  m.rescuer_id("r1");
  ::sarloc::Odometry o;
  o.rescuer_id("r2");
  ::sarloc::VictimEstimate e;
  e.rescuer_id("r3");
  ::sarloc::ResponderAlarm a;
  a.responder_id("ff1");
  ::sarloc::ResponderPosition gnss;
  gnss.responder_id("ff2");
  gnss.source(::sarloc::POSITION_GNSS);
  ::sarloc::ResponderPosition map_aided = gnss;
  map_aided.source(::sarloc::POSITION_MAP_AIDED);
  struct Case {
    SpeakerClaim claim;
    std::string id;
    Speakers speakers;
  };
  for (const Case& c :
       {Case{speaker_claim(m), "r1", Speakers::kDevice}, Case{speaker_claim(o), "r2", Speakers::kDevice},
        Case{speaker_claim(e), "r3", Speakers::kDeviceOrCore}, Case{speaker_claim(a), "ff1", Speakers::kDevice},
        Case{speaker_claim(gnss), "ff2", Speakers::kDevice},
        Case{speaker_claim(map_aided), "ff2", Speakers::kDeviceOrCore}}) {
    EXPECT_EQ(c.claim.responder_id, c.id) << c.claim.what;
    EXPECT_EQ(c.claim.speakers, c.speakers) << c.claim.what;
  }
}

TEST(SpeakerClaim, ARawPayloadClaimsWhatItsDecodedSampleClaims) {
  ::sarloc::ResponderPosition p;
  p.responder_id("ff2");
  p.source(::sarloc::POSITION_MAP_AIDED);
  const auto claim = raw_speaker_claim("sarloc/responder_position", payload(p));
  ASSERT_TRUE(claim);
  EXPECT_EQ(claim->responder_id, "ff2");
  EXPECT_EQ(claim->speakers, Speakers::kDeviceOrCore);
  ::sarloc::ResponderAlarm a;
  a.responder_id("r1");
  const auto alarm = raw_speaker_claim("sarloc/responder_alarm", payload(a));
  ASSERT_TRUE(alarm);
  EXPECT_EQ(alarm->responder_id, "r1");
  EXPECT_EQ(alarm->speakers, Speakers::kDevice);
  // The picture and the plan speak for no responder: their DDS Security grant is their check.
  ::sarloc::FusedVictim v;
  v.victim_id(4);
  EXPECT_FALSE(raw_speaker_claim("sarloc/fused_victim", payload(v)));
  EXPECT_FALSE(raw_speaker_claim("sarloc/not_a_topic", {1, 2}));
}

TEST(SpeakerClaim, ARawPayloadThatDoesNotDecodeOrNamesNoIdentifierIsRefused) {
  EXPECT_THROW(raw_speaker_claim("sarloc/responder_alarm", {}), InputError);
  EXPECT_THROW(raw_speaker_claim("sarloc/odometry", {0x00, 0x01}), InputError);
  ::sarloc::Odometry o;
  o.rescuer_id("bad\xff\xfeid");
  try {
    raw_speaker_claim("sarloc/odometry", payload(o));
    ADD_FAILURE() << "an id that is not an identifier was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("sarloc/odometry responder id"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("\\xFF"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace sarloc::dds
