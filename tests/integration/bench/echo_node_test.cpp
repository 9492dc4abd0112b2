// The latency bench's echo (apps/bench_latency/echo_node.hpp) answers every field measurement
// with a VictimEstimate carrying its rescuer, signal, stamp and sequence, on every hand-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "echo_node.hpp"
#include "sarloc/dds/conversions.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"
#include "support/sample_messages.hpp"

namespace sarloc::bench {
namespace {

using namespace std::chrono_literals;

void expect_echo(std::uint32_t domain, EchoHandoff handoff) {
  auto device = test::make_participant(domain, "device");
  EchoNodeConfig config;
  config.handoff = handoff;
  EchoNode echo(test::make_participant(domain, "echo"), config);
  test::Inbox<::sarloc::VictimEstimate> inbox;
  dds::Reader<::sarloc::VictimEstimate> estimates(device, [&](const auto& e, const auto&) { inbox.push(e); });
  dds::Writer<::sarloc::FieldMeasurement> measurements(device);
  ASSERT_TRUE(measurements.wait_for_readers(1, 10s));
  ASSERT_TRUE(estimates.wait_for_writers(1, 10s));
  std::vector<::sarloc::FieldMeasurement> sent;
  for (std::uint32_t signal = 1; signal <= 3; ++signal) {
    auto m = dds::to_idl(test::sample_field_measurement());
    m.signal_id(signal);
    m.sequence_number(40 + signal);
    m.stamp(m.stamp() + signal);
    ASSERT_TRUE(measurements.write(m));
    sent.push_back(m);
  }
  const auto got = inbox.wait_for(sent.size(), 10s);
  ASSERT_EQ(got.size(), sent.size()) << to_string(handoff);
  // One instance per signal: DDS orders samples per instance only (a WaitSet take can return
  // the instances in another order).
  for (const auto& m : sent) {
    const auto it = std::find_if(got.begin(), got.end(), [&](const auto& e) { return e.signal_id() == m.signal_id(); });
    ASSERT_NE(it, got.end()) << "no answer for signal " << m.signal_id();
    EXPECT_EQ(it->rescuer_id().to_string(), m.rescuer_id().to_string());
    EXPECT_EQ(it->measurement_sequence(), m.sequence_number());
    EXPECT_EQ(it->stamp(), m.stamp());
  }
  // Counted once write() returned, which can be after the answer arrived.
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (echo.echoed() < sent.size() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);
  EXPECT_EQ(echo.echoed(), sent.size());
  EXPECT_EQ(echo.refused(), 0U);
}

TEST(EchoNode, AnswersEveryMeasurementOnTheListenerThread) {
  expect_echo(test::kDomainBenchEchoListener, EchoHandoff::kListener);
}

TEST(EchoNode, AnswersEveryMeasurementThroughItsWorker) {
  expect_echo(test::kDomainBenchEchoQueue, EchoHandoff::kQueue);
}

TEST(EchoNode, AnswersEveryMeasurementFromAWaitSet) {
  expect_echo(test::kDomainBenchEchoWaitSet, EchoHandoff::kWaitSet);
}

TEST(EchoNode, RefusesAnUnknownHandoff) {
  EXPECT_THROW(parse_echo_handoff("polling"), ConfigError);
}

}  // namespace
}  // namespace sarloc::bench
