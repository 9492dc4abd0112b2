// Every topic type goes through real Fast DDS participants on loopback (localhost profile)
// and arrives equal to what was sent.
#include <gtest/gtest.h>

#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"
#include "support/sample_messages.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;

// Two participants (as two processes would have), one writer, one reader; sends `samples`
// and expects them back equal and in order.
template <class T>
void expect_round_trip(std::uint32_t domain, const std::vector<T>& samples) {
  auto sender = test::make_participant(domain, "sender");
  auto receiver = test::make_participant(domain, "receiver");
  test::Inbox<T> inbox;
  Reader<T> reader(receiver, [&](const T& s, const auto&) { inbox.push(s); });
  Writer<T> writer(sender);
  ASSERT_TRUE(writer.wait_for_readers(1, 10s)) << TopicTraits<T>::kName << ": no reader matched";
  for (const auto& s : samples) ASSERT_TRUE(writer.write(s));
  const auto got = inbox.wait_for(samples.size(), 10s);
  ASSERT_EQ(got.size(), samples.size()) << TopicTraits<T>::kName;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_TRUE(got[i] == samples[i]) << TopicTraits<T>::kName << " sample " << i << " differs";
  }
}

constexpr std::uint32_t kBase = test::kDomainRoundTripFirst;

TEST(DdsRoundTrip, FieldMeasurement) {
  auto a = to_idl(test::sample_field_measurement());
  auto b = a;
  b.signal_id(8);  // another instance of the keyed topic
  b.field().x(-4.0e-6);
  expect_round_trip<::sarloc::FieldMeasurement>(kBase + 0, {a, b});
}

TEST(DdsRoundTrip, Odometry) {
  auto a = to_idl(test::sample_odometry());
  auto b = a;
  b.sequence_number(a.sequence_number() + 1);
  expect_round_trip<::sarloc::Odometry>(kBase + 1, {a, b});
}

TEST(DdsRoundTrip, VictimEstimate) {
  expect_round_trip<::sarloc::VictimEstimate>(kBase + 2, {to_idl(test::sample_victim_estimate(), 12)});
}

TEST(DdsRoundTrip, Guidance) {
  expect_round_trip<::sarloc::Guidance>(kBase + 3, {to_idl(test::sample_guidance(), 3)});
}

TEST(DdsRoundTrip, ResponderPosition) {
  expect_round_trip<::sarloc::ResponderPosition>(kBase + 4, {to_idl(test::sample_responder_position())});
}

TEST(DdsRoundTrip, ResponderCandidates) {
  expect_round_trip<::sarloc::ResponderCandidates>(kBase + 16, {to_idl(test::sample_responder_candidates())});
}

TEST(DdsRoundTrip, FusedVictim) {
  expect_round_trip<::sarloc::FusedVictim>(kBase + 5, {to_idl(test::sample_fused_victim())});
}

TEST(DdsRoundTrip, TeamStatus) {
  expect_round_trip<::sarloc::TeamStatus>(kBase + 6, {to_idl(test::sample_team_status())});
}

TEST(DdsRoundTrip, IncidentFrame) {
  ::sarloc::IncidentFrame f;
  f.incident_id("avalanche-2026-11-21");
  f.latitude_deg(46.5197);
  f.longitude_deg(7.9627);
  f.altitude_m(2450.5);
  f.name("Lauberhorn slope, debris cone B");
  f.established(1763731100000000000LL);
  expect_round_trip<::sarloc::IncidentFrame>(kBase + 7, {f});
}

TEST(DdsRoundTrip, IncidentSummary) {
  ::sarloc::IncidentSummary s;
  s.incident_id("avalanche-2026-11-21");
  s.stamp(1763731300000000000LL);
  s.victims_total(3);
  s.victims_located(2);
  s.victims_found(1);
  s.responders_total(5);
  s.responders_link_lost(1);
  expect_round_trip<::sarloc::IncidentSummary>(kBase + 8, {s});
}

TEST(DdsRoundTrip, NodeStatus) {
  ::sarloc::NodeStatus s;
  s.node_id("core-sector-a");
  s.kind(::sarloc::NODE_CORE);
  s.stamp(1763731300000000000LL);
  s.samples_accepted(1000);
  s.samples_rejected(7);
  ::sarloc::RejectCount r;
  r.reason("non_finite");
  r.count(5);
  s.rejects().push_back(r);
  r.reason("stamp_backwards");
  r.count(2);
  s.rejects().push_back(r);
  s.active_filters(12);
  s.rescuers_served(4);
  s.cpu_percent(37.5);
  s.rss_mb(88.25);
  expect_round_trip<::sarloc::NodeStatus>(kBase + 9, {s});
}

TEST(DdsRoundTrip, ResponderAlarm) {
  auto a = to_idl(test::sample_responder_alarm());
  auto b = a;
  b.kind(::sarloc::ALARM_MAYDAY);  // another instance: the kind is part of the key
  b.active(true);
  b.cleared_at(0);
  expect_round_trip<::sarloc::ResponderAlarm>(kBase + 10, {a, b});
  EXPECT_EQ(to_core(a).kind, responder::AlarmKind::kMotionless);
  EXPECT_EQ(to_core(a).cleared_at, test::sample_responder_alarm().cleared_at);
}

TEST(DdsRoundTrip, IncidentAlarm) {
  const auto a = to_idl(test::sample_incident_alarm());
  expect_round_trip<::sarloc::IncidentAlarm>(kBase + 11, {a});
  const auto back = to_core(a);
  EXPECT_EQ(back.alarm_id, 42U);
  EXPECT_EQ(back.acknowledged_by, "ic-chief");
  EXPECT_EQ(back.alarm.kind, responder::AlarmKind::kMayday);
  EXPECT_EQ(back.alarm.floor, 1);
}

TEST(DdsRoundTrip, AlarmAcknowledgement) {
  ::sarloc::AlarmAcknowledgement ack;
  ack.alarm_id(42);
  ack.operator_id("ic-chief");
  ack.stamp(1763731340000000000LL);
  expect_round_trip<::sarloc::AlarmAcknowledgement>(kBase + 12, {ack});
}

TEST(DdsRoundTrip, VictimRecovery) {
  ::sarloc::VictimRecovery recovery;
  recovery.victim_id(3);
  recovery.reported_by("r2");
  recovery.stamp(1763731350000000000LL);
  expect_round_trip<::sarloc::VictimRecovery>(kBase + 13, {recovery});
}

TEST(DdsRoundTrip, DigOrder) {
  ::sarloc::DigOrder order;
  order.incident_id("avalanche-large");
  order.victim_ids({9, 7, 12});
  order.operator_id("ic-chief");
  order.stamp(1763731360000000000LL);
  expect_round_trip<::sarloc::DigOrder>(kBase + 14, {order});
}

TEST(DdsRoundTrip, DepositDrawing) {
  ::sarloc::DepositDrawing drawing;
  drawing.incident_id("avalanche-large");
  drawing.stamp(1763731360000000000LL);
  drawing.operator_id("ic-chief");
  for (const auto& [x, y] : {std::pair{-20.5, 0.0}, {60.0, -3.25}, {70.0, 80.0}, {-15.0, 75.5}}) {
    ::sarloc::PlanePoint p;
    p.x(x);
    p.y(y);
    drawing.outline().push_back(p);
  }
  expect_round_trip<::sarloc::DepositDrawing>(kBase + 15, {drawing});
}

}  // namespace
}  // namespace sarloc::dds
