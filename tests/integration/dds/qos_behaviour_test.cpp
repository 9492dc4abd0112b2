// The per-topic QoS in config/dds/topics.xml does what docs/topics.md promises.
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

// The incident picture is TRANSIENT_LOCAL: a dashboard that subscribes late gets the current
// state of every instance at once, and only the newest sample of each (KEEP_LAST 1).
TEST(QosBehaviour, LateJoinerReceivesTheNewestPictureAtOnce) {
  auto aggregator = test::make_participant(test::kDomainLateJoiner, "aggregator");
  Writer<::sarloc::FusedVictim> writer(aggregator);
  auto v1 = to_idl(test::sample_fused_victim());
  auto v2 = v1;
  v2.victim_id(v1.victim_id() + 1);
  auto v1_newer = v1;
  v1_newer.state(::sarloc::VICTIM_RECOVERED);
  ASSERT_TRUE(writer.write(v1));
  ASSERT_TRUE(writer.write(v2));
  ASSERT_TRUE(writer.write(v1_newer));

  auto dashboard = test::make_participant(test::kDomainLateJoiner, "dashboard");
  test::Inbox<::sarloc::FusedVictim> inbox;
  Reader<::sarloc::FusedVictim> reader(dashboard, [&](const auto& s, const auto&) { inbox.push(s); });
  auto got = inbox.wait_for(2, 10s);
  std::this_thread::sleep_for(300ms);  // anything beyond the two newest would show up now
  got = inbox.wait_for(2, 0s);
  ASSERT_EQ(got.size(), 2U);
  bool saw_v1_newer = false;
  bool saw_v2 = false;
  for (const auto& s : got) {
    saw_v1_newer |= s == v1_newer;
    saw_v2 |= s == v2;
  }
  EXPECT_TRUE(saw_v1_newer);
  EXPECT_TRUE(saw_v2);
}

// Sectors: a core daemon in partition "sector-a" never sees sector B's rescuers.
TEST(QosBehaviour, PartitionsKeepSectorsApart) {
  auto rescuers = test::make_participant(test::kDomainPartitions, "rescuers");
  auto core_a = test::make_participant(test::kDomainPartitions, "core-a");
  test::Inbox<::sarloc::FieldMeasurement> inbox;
  EndpointOptions sector_a;
  sector_a.partitions = {"sector-a"};
  EndpointOptions sector_b;
  sector_b.partitions = {"sector-b"};
  Reader<::sarloc::FieldMeasurement> reader(core_a, [&](const auto& s, const auto&) { inbox.push(s); }, sector_a);
  Writer<::sarloc::FieldMeasurement> writer_a(rescuers, sector_a);
  Writer<::sarloc::FieldMeasurement> writer_b(rescuers, sector_b);
  ASSERT_TRUE(writer_a.wait_for_readers(1, 10s));
  std::this_thread::sleep_for(500ms);
  EXPECT_EQ(writer_b.matched_readers(), 0) << "sector B's writer matched sector A's reader";

  auto in_a = to_idl(test::sample_field_measurement());
  in_a.rescuer_id("in-sector-a");
  auto in_b = in_a;
  in_b.rescuer_id("in-sector-b");
  ASSERT_TRUE(writer_b.write(in_b));
  ASSERT_TRUE(writer_a.write(in_a));
  auto got = inbox.wait_for(1, 10s);
  std::this_thread::sleep_for(300ms);
  got = inbox.wait_for(1, 0s);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].rescuer_id().to_string(), "in-sector-a");
}

// Responder positions carry a 3 s liveliness lease: the reader hears when a writer goes away.
TEST(QosBehaviour, ReaderHearsWhenAResponderWriterDisappears) {
  auto command = test::make_participant(test::kDomainLiveliness, "command");
  std::mutex mutex;
  std::condition_variable cv;
  int alive = 0;
  int lost = 0;
  ReaderEvents events;
  events.on_liveliness = [&](const auto&, bool is_alive) {
    std::lock_guard<std::mutex> lock(mutex);
    (is_alive ? alive : lost)++;
    cv.notify_all();
  };
  Reader<::sarloc::ResponderPosition> reader(command, [](const auto&, const auto&) {}, {}, events);
  {
    auto rescuer = test::make_participant(test::kDomainLiveliness, "rescuer");
    Writer<::sarloc::ResponderPosition> writer(rescuer);
    ASSERT_TRUE(writer.wait_for_readers(1, 10s));
    ASSERT_TRUE(writer.write(to_idl(test::sample_responder_position())));
    std::unique_lock<std::mutex> lock(mutex);
    ASSERT_TRUE(cv.wait_for(lock, 10s, [&] { return alive > 0; })) << "never saw the writer alive";
  }  // the rescuer's participant is gone
  std::unique_lock<std::mutex> lock(mutex);
  EXPECT_TRUE(cv.wait_for(lock, 10s, [&] { return lost > 0; })) << "writer loss never reported";
}

}  // namespace
}  // namespace sarloc::dds
