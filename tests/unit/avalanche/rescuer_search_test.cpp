// RescuerSearch: the per-rescuer gate, one filter per signal, the target choice and coasting.
#include "sarloc/core/avalanche/rescuer_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sarloc/core/mission/simulated_rescuer.hpp"

namespace sarloc::avalanche {
namespace {

mission::MissionScenario scenario() {
  mission::MissionScenario s;
  // A is much closer than B: its signal is the strongest.
  s.victims = {{"A", Vec3(0.0, 15.0, -1.0), Vec3(0.01, -0.005, 0.004)},
               {"B", Vec3(30.0, 35.0, -1.5), Vec3(-0.004, 0.003, 0.015)}};
  s.rescuers = {{"r", "t", Vec3(0.0, 0.0, 0.0), 90.0}};
  s.seed = 5;
  return s;
}

RescuerSearchConfig quick() {
  RescuerSearchConfig c;
  c.sog.initial_components = 300;
  return c;
}

constexpr TimestampNs kSecond = 1'000'000'000;

// Feeds `epochs` epochs walking straight north, the guidance ignored; returns the last epoch.
std::vector<FieldMeasurement> feed(RescuerSearch& search, mission::SimulatedRescuer& sim, int epochs) {
  std::vector<FieldMeasurement> last;
  for (int k = 0; k < epochs; ++k) {
    if (k > 0) {
      EXPECT_FALSE(search.add_odometry(sim.walk(0.0, 0.5, k * kSecond, (k + 1) * kSecond)).has_value());
    }
    last = sim.measure((k + 1) * kSecond);
    for (const auto& m : last) EXPECT_TRUE(std::holds_alternative<SearchUpdate>(search.process(m)));
  }
  return last;
}

TEST(RescuerSearch, OneFilterPerSignalAndGuidanceOnlyForTheTarget) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  const auto first = sim.measure(kSecond);
  ASSERT_EQ(first.size(), 2U);
  int guided = 0;
  for (const auto& m : first) {
    auto out = search.process(m);
    ASSERT_TRUE(std::holds_alternative<SearchUpdate>(out));
    if (std::get<SearchUpdate>(out).guidance) ++guided;
  }
  EXPECT_EQ(search.signal_count(), 2U);
  EXPECT_LE(guided, 1) << "the rescuer must get one direction, not one per signal";
  ASSERT_TRUE(search.target_signal().has_value());
  const auto strongest = first[0].field.norm() > first[1].field.norm() ? first[0].signal_id : first[1].signal_id;
  EXPECT_EQ(*search.target_signal(), strongest);
  EXPECT_EQ(sim.victim_of_signal(strongest), 0U) << "the nearer victim has the strongest signal";
}

TEST(RescuerSearch, RefusedSamplesNameTheirReasonAndLeaveTheFiltersAlone) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  const auto last = feed(search, sim, 3);
  const auto before = search.estimate(last.front().signal_id);
  ASSERT_TRUE(before.has_value());

  auto expect_refused = [&](FieldMeasurement m, RejectReason reason, const std::string& text) {
    auto out = search.process(m);
    ASSERT_TRUE(std::holds_alternative<Rejection>(out)) << text;
    EXPECT_EQ(std::get<Rejection>(out).reason, reason) << text;
    EXPECT_NE(std::get<Rejection>(out).detail.find("rescuer 'r'"), std::string::npos) << std::get<Rejection>(out).detail;
  };
  auto dup = last.front();
  expect_refused(dup, RejectReason::kDuplicateSequence, "duplicate");
  auto old = last.front();
  old.sequence -= 1;
  old.stamp += kSecond;
  expect_refused(old, RejectReason::kSequenceBackwards, "older sequence");
  auto same_stamp = last.front();
  same_stamp.sequence += 1;
  expect_refused(same_stamp, RejectReason::kStampBackwards, "same stamp");
  auto nan = last.front();
  nan.sequence += 1;
  nan.stamp += kSecond;
  nan.field.x() = std::numeric_limits<double>::quiet_NaN();
  expect_refused(nan, RejectReason::kInvalidValue, "NaN");
  auto other = last.front();
  other.rescuer_id = "someone-else";
  expect_refused(other, RejectReason::kWrongRescuer, "wrong rescuer");
  for (std::uint32_t extra = 100; extra < 100 + quick().max_signals; ++extra) {
    auto m = last.front();
    m.signal_id = extra;
    (void)search.process(m);
  }
  auto too_many = last.front();
  too_many.signal_id = 999;
  expect_refused(too_many, RejectReason::kTooManySignals, "too many signals");

  Odometry jump;
  jump.rescuer_id = "r";
  jump.sequence = 1000;
  jump.interval_start = 10 * kSecond;
  jump.interval_end = 11 * kSecond;
  jump.translation = Vec3(500.0, 0.0, 0.0);
  jump.covariance = Mat6::Identity() * 1e-4;
  auto refused = search.add_odometry(jump);
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->reason, RejectReason::kAbsurdMotion);

  const auto after = search.estimate(last.front().signal_id);
  EXPECT_EQ(after->relative.position, before->relative.position);
  EXPECT_EQ(after->relative.covariance, before->relative.covariance);
}

TEST(RescuerSearch, MarkDoneMovesTheTargetAndNeverGuidesToAFoundVictim) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  const auto last = feed(search, sim, 4);
  ASSERT_TRUE(search.target_signal().has_value());
  const auto first_target = *search.target_signal();
  search.mark_done(first_target);
  ASSERT_TRUE(search.target_signal().has_value());
  EXPECT_NE(*search.target_signal(), first_target);
  search.mark_done(*search.target_signal());
  EXPECT_FALSE(search.target_signal().has_value());
  sim.walk(0.0, 0.5, 4 * kSecond, 5 * kSecond);
  for (const auto& m : sim.measure(5 * kSecond)) {
    auto out = search.process(m);
    ASSERT_TRUE(std::holds_alternative<SearchUpdate>(out));
    EXPECT_FALSE(std::get<SearchUpdate>(out).guidance.has_value()) << "guided towards a found victim";
  }
}

TEST(RescuerSearch, CoastingMovesTheTargetByTheStepsTakenSinceItWasHeard) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  feed(search, sim, 16);  // long enough for the near victim to converge, still metres away
  const auto target = search.target_signal();
  ASSERT_TRUE(target.has_value());
  const auto heard = search.coast(17 * kSecond);
  ASSERT_TRUE(heard.has_value());
  // Walk half way straight towards the estimate without hearing anything.
  const double step = 0.5 * heard->distance_m;
  ASSERT_GT(step, 1.0) << "the test needs the target a few metres away";
  auto odo = sim.walk(heard->bearing_rad, step, 16 * kSecond, 17 * kSecond);
  ASSERT_FALSE(search.add_odometry(odo).has_value());
  const auto coasted = search.coast(17 * kSecond);
  ASSERT_TRUE(coasted.has_value());
  EXPECT_EQ(coasted->signal_id, *target);
  EXPECT_NEAR(coasted->distance_m, heard->distance_m - step, 0.1 * step + 0.2);
  EXPECT_LT(std::fabs(coasted->bearing_rad), 0.35) << "after walking at it, the target is still ahead";
  // Truth agrees with the coasted estimate's distance.
  const double true_distance = (s.victims[*sim.victim_of_signal(*target)].position - sim.pose().position).head<2>().norm();
  EXPECT_NEAR(coasted->distance_m, true_distance, 1.5);
}

}  // namespace
}  // namespace sarloc::avalanche
