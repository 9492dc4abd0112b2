// The per-topic QoS in config/dds/topics.xml does what docs/topics.md promises.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/topic/Topic.hpp>

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

// The writers of the many-instance topics whose instances stop being written carry a lifespan
// (docs/topics.md, "Lifespan bounds what every heartbeat carries"): without it, Fast DDS 2.9's
// heartbeat GAPs for every hole in the history grew with everything written since, and at 200
// rescuers incident command, the recorder and the load generator each climbed to half a core in
// five minutes. It must also outlast the history a fade is repaired from: depth x 1 s.
TEST(QosBehaviour, ManyInstanceWritersForgetOldSamplesButNotBeforeAFadeIsRepaired) {
  auto participant = test::make_participant(test::kDomainWriterLifespan, "writers");
  auto lifespan_s = [](const eprosima::fastdds::dds::DataWriter* w) {
    const auto& d = w->get_qos().lifespan().duration;
    return d == eprosima::fastrtps::c_TimeInfinite ? -1.0 : d.seconds + d.nanosec * 1e-9;
  };
  auto depth = [](const eprosima::fastdds::dds::DataWriter* w) { return w->get_qos().history().depth; };
  Writer<::sarloc::FieldMeasurement> field(participant);
  Writer<::sarloc::Odometry> odometry(participant);
  Writer<::sarloc::VictimEstimate> estimate(participant);
  Writer<::sarloc::Guidance> guidance(participant);
  for (const auto* w : {field.get(), odometry.get(), estimate.get(), guidance.get()}) {
    const double life = lifespan_s(w);
    EXPECT_GT(life, 0.0) << w->get_topic()->get_name() << ": no lifespan";
    EXPECT_LE(life, 600.0) << w->get_topic()->get_name();
    EXPECT_GE(life, depth(w) * 1.0) << w->get_topic()->get_name() << ": a fade's repair would be cut short";
  }
  // Incident command drops a source after fusion.source_timeout_s (10 s); an estimate must live longer.
  EXPECT_GE(lifespan_s(estimate.get()), 10.0);
  // The core daemon's map-aided positions of every firefighter (2 Hz): a lifespan too, within
  // which it writes a silent one's last position again (estimator::PositionRefresh); a device's
  // own writer holds one instance, itself, and keeps its last position for late readers.
  Writer<::sarloc::ResponderPosition> map_aided(participant);
  Writer<::sarloc::ResponderPosition> device(participant, device_position_options());
  EXPECT_GT(lifespan_s(map_aided.get()), 0.0) << "the daemon's positions: no lifespan";
  EXPECT_GE(lifespan_s(map_aided.get()), depth(map_aided.get()) * 0.5) << "a fade's repair would be cut short";
  EXPECT_LT(lifespan_s(device.get()), 0.0) << "a device's own last position must stay";
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

// The picture topics are OWNERSHIP EXCLUSIVE (hot-standby incident command): a reader takes an
// instance only from its strongest live writer; Fast DDS 2.9 honours a strength raised at run
// time with set_qos; a writer that stops asserting its MANUAL_BY_TOPIC liveliness (a killed or
// hung instance) loses the instance about 3 s (the lease) after its last write; and a weaker
// writer cannot dispose of what the stronger one owns.
TEST(QosBehaviour, PictureOwnershipFollowsTheStrongestLiveWriter) {
  auto dashboard = test::make_participant(test::kDomainOwnership, "dashboard");
  auto one = test::make_participant(test::kDomainOwnership, "command-1");
  auto two = test::make_participant(test::kDomainOwnership, "command-2");
  std::mutex mutex;
  std::condition_variable cv;
  std::vector<std::uint32_t> taken;  // victims_total carries the writer's tag
  int lost = 0;
  ReaderEvents events;
  events.on_liveliness = [&](const auto&, bool alive) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!alive) ++lost;
    cv.notify_all();
  };
  Reader<::sarloc::IncidentSummary> reader(
      dashboard,
      [&](const ::sarloc::IncidentSummary& s, const auto&) {
        std::lock_guard<std::mutex> lock(mutex);
        taken.push_back(s.victims_total());
        cv.notify_all();
      },
      {}, events);
  Writer<::sarloc::IncidentSummary> w1(one);
  Writer<::sarloc::IncidentSummary> w2(two);
  ASSERT_TRUE(w1.wait_for_readers(1, 10s));
  ASSERT_TRUE(w2.wait_for_readers(1, 10s));
  w1.set_ownership_strength(100);
  w2.set_ownership_strength(50);
  std::this_thread::sleep_for(300ms);  // the new strengths travel by discovery
  auto tagged = [](std::uint32_t tag) {
    ::sarloc::IncidentSummary s;
    s.incident_id("ownership");
    s.victims_total(tag);
    return s;
  };
  auto write_both = [&](std::uint32_t tag1, std::uint32_t tag2) {
    for (int i = 0; i < 5; ++i) {
      ASSERT_TRUE(w1.write(tagged(tag1)));
      ASSERT_TRUE(w2.write(tagged(tag2)));
      std::this_thread::sleep_for(50ms);
    }
    std::this_thread::sleep_for(300ms);
  };
  auto taken_since = [&](std::size_t from) {
    std::lock_guard<std::mutex> lock(mutex);
    return std::vector<std::uint32_t>(taken.begin() + static_cast<std::ptrdiff_t>(from), taken.end());
  };
  write_both(1, 2);
  auto got = taken_since(0);
  ASSERT_FALSE(got.empty());
  for (const auto tag : got) EXPECT_EQ(tag, 1U) << "the weaker writer's sample reached the reader";

  // The standby becomes the stronger one at run time.
  std::size_t mark = taken_since(0).size();
  w2.set_ownership_strength(200);
  std::this_thread::sleep_for(300ms);
  write_both(3, 4);
  got = taken_since(mark);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back(), 4U) << "a strength raised with set_qos was not honoured";

  // The stronger one stops writing (killed, hung): the weaker one's samples get through once
  // its lease (3 s, MANUAL_BY_TOPIC) has run out.
  mark = taken_since(0).size();
  const auto stopped = std::chrono::steady_clock::now();
  double handed_over_s = -1.0;
  while (std::chrono::steady_clock::now() - stopped < 8s) {
    ASSERT_TRUE(w1.write(tagged(5)));
    std::this_thread::sleep_for(50ms);
    got = taken_since(mark);
    if (std::find(got.begin(), got.end(), 5U) != got.end()) {
      handed_over_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - stopped).count();
      break;
    }
  }
  EXPECT_GE(handed_over_s, 2.5) << "taken before the stronger writer's lease ran out";
  EXPECT_LE(handed_over_s, 3.6) << "not within the 3 s lease (-1: never)";
  {
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_GE(lost, 1) << "the lost writer was not reported";
  }

  // A weaker writer's dispose of an instance the stronger one owns is ignored.
  Writer<::sarloc::FusedVictim> strong(one);
  Writer<::sarloc::FusedVictim> weak(two);
  strong.set_ownership_strength(100);
  weak.set_ownership_strength(50);
  std::atomic<int> disposed{0};
  ReaderEvents victim_events;
  victim_events.on_instance_gone = [&](const auto& info) {
    if (info.instance_state == eprosima::fastdds::dds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) disposed.fetch_add(1);
  };
  test::Inbox<::sarloc::FusedVictim> victims;
  Reader<::sarloc::FusedVictim> victim_reader(
      dashboard, [&](const auto& v, const auto&) { victims.push(v); }, {}, victim_events);
  ASSERT_TRUE(strong.wait_for_readers(1, 10s));
  ASSERT_TRUE(weak.wait_for_readers(1, 10s));
  std::this_thread::sleep_for(300ms);
  const auto v = to_idl(test::sample_fused_victim());
  ASSERT_TRUE(strong.write(v));
  ASSERT_EQ(victims.wait_for(1, 10s).size(), 1U);
  ASSERT_TRUE(weak.write(v));  // ignored too
  EXPECT_TRUE(weak.dispose(v));
  std::this_thread::sleep_for(500ms);
  EXPECT_EQ(disposed.load(), 0) << "a weaker writer disposed of the stronger one's victim";
  EXPECT_TRUE(strong.dispose(v));
  const auto until = std::chrono::steady_clock::now() + 5s;
  while (disposed.load() == 0 && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(10ms);
  EXPECT_EQ(disposed.load(), 1) << "the owner's dispose did not arrive";
}

}  // namespace
}  // namespace sarloc::dds
