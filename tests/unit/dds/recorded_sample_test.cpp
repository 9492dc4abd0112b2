// A recorded sample read back (recorded_sample.hpp): the one decoding the report and the
// dashboard's replay share.
#include "sarloc/dds/recorded_sample.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/dds/raw_topic_type.hpp"
#include "sarloc/dds/topics.hpp"
#include "support/sample_messages.hpp"

namespace sarloc::dds {
namespace {

template <class Idl>
std::vector<std::uint8_t> recorded(const Idl& sample) {
  return encode_payload<typename TopicTraits<Idl>::PubSubType>(sample);
}

TEST(RecordedSample, ASampleOfEachTopicReadsBackAsTheCoreTypeALiveReaderGets) {
  const auto position = test::sample_responder_position();
  const auto decoded = decode_recorded("sarloc/responder_position", recorded(to_idl(position)));
  ASSERT_TRUE(decoded.has_value());
  const auto* p = std::get_if<responder::ResponderPosition>(&*decoded);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->responder_id, position.responder_id);
  EXPECT_EQ(p->stamp, position.stamp);
  EXPECT_EQ(p->position.position, position.position.position);

  const auto victim = test::sample_fused_victim();
  const auto v = decode_recorded("sarloc/fused_victim", recorded(to_idl(victim)));
  ASSERT_TRUE(v.has_value());
  ASSERT_TRUE(std::holds_alternative<incident::FusedVictim>(*v));
  EXPECT_EQ(std::get<incident::FusedVictim>(*v).victim_id, victim.victim_id);

  ::sarloc::VictimRecovery recovery;
  recovery.victim_id(7);
  recovery.reported_by("ic1");
  const auto r = decode_recorded("sarloc/victim_recovery", recorded(recovery));
  ASSERT_TRUE(r.has_value());
  ASSERT_TRUE(std::holds_alternative<::sarloc::VictimRecovery>(*r));
  EXPECT_EQ(std::get<::sarloc::VictimRecovery>(*r).victim_id(), 7U);
}

TEST(RecordedSample, ATopicWithNoReadingHereIsNoSample) {
  EXPECT_FALSE(decode_recorded("sarloc/recorder_events", {'{', '}'}).has_value());
  EXPECT_FALSE(decode_recorded("not/a/topic", {1, 2, 3}).has_value());
}

TEST(RecordedSample, BytesThatDoNotDecodeOrThatTheCoreRefusesThrowNamingTheTopic) {
  try {
    (void)decode_recorded("sarloc/team_status", {0x00, 0x01});
    FAIL() << "two bytes decoded as a TeamStatus";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sarloc/team_status"), std::string::npos) << e.what();
  }
  auto position = to_idl(test::sample_responder_position());
  position.source(static_cast<::sarloc::PositionSource>(99));  // none such: the core refuses it
  EXPECT_THROW((void)decode_recorded("sarloc/responder_position", recorded(position)), InputError);
}

}  // namespace
}  // namespace sarloc::dds
