// RescuerSearch: the per-rescuer gate, one filter per signal, the target choice and coasting.
#include "sarloc/core/avalanche/rescuer_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "rescuer_search_world.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/mission/simulated_rescuer.hpp"
#include "support/config_messages.hpp"

namespace sarloc::avalanche {
namespace {

using test::feed;
using test::kSecond;
using test::quick;
using test::scenario;

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

TEST(RescuerSearch, TheLastSeparationEventOfASignalStaysInItsEstimate) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  auto epoch = feed(search, sim, 3);
  ASSERT_FALSE(epoch.empty());
  const std::uint32_t signal = epoch.front().signal_id;
  EXPECT_EQ(search.estimate(signal)->signal_event, SignalEvent::kNone);
  ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.5, 3 * kSecond, 4 * kSecond)).has_value());
  epoch = sim.measure(4 * kSecond);
  for (auto& m : epoch) {
    if (m.signal_id == signal) m.event = SignalEvent::kSeparated;
    const auto out = search.process(m);
    ASSERT_TRUE(std::holds_alternative<SearchUpdate>(out));
    if (m.signal_id == signal) {
      EXPECT_EQ(std::get<SearchUpdate>(out).estimate->signal_event, SignalEvent::kSeparated);
    }
  }
  // Later samples carry no event: the estimate keeps the last one and its stamp.
  ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.5, 4 * kSecond, 5 * kSecond)).has_value());
  for (const auto& m : sim.measure(5 * kSecond)) ASSERT_TRUE(std::holds_alternative<SearchUpdate>(search.process(m)));
  EXPECT_EQ(search.estimate(signal)->signal_event, SignalEvent::kSeparated);
  EXPECT_EQ(search.estimate(signal)->signal_event_stamp, 4 * kSecond);
}

// The separation's question: which signal's filter explains this field? Its own, by far.
TEST(RescuerSearch, ASignalsFilterExplainsItsOwnSamplesFarBetterThanAnothers) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  feed(search, sim, 15);
  ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.5, 15 * kSecond, 16 * kSecond)).has_value());
  const auto next = sim.measure(16 * kSecond);
  ASSERT_EQ(next.size(), 2U);
  for (const auto& m : next) {
    const std::uint32_t other = m.signal_id == next[0].signal_id ? next[1].signal_id : next[0].signal_id;
    const auto own = search.field_fit(m.signal_id, m.field, m.noise_stddev, m.valid_axes);
    const auto foreign = search.field_fit(other, m.field, m.noise_stddev, m.valid_axes);
    ASSERT_TRUE(own && foreign);
    EXPECT_GT(own->log_likelihood - foreign->log_likelihood, 9.2) << "signal " << m.signal_id;  // the separator's margin
    // Sign-invariant: the receiver does not know the field's sign.
    const auto flipped = search.field_fit(m.signal_id, -m.field, m.noise_stddev, m.valid_axes);
    EXPECT_NEAR(flipped->log_likelihood, own->log_likelihood, 1e-9);
    EXPECT_NEAR(flipped->nis, own->nis, 1e-9);
  }
  EXPECT_FALSE(search.field_fit(99, next[0].field, next[0].noise_stddev, 7).has_value());
}

// The target gives way when it has been silent for target_silence_s while another is heard.
TEST(RescuerSearch, ASilentTargetGivesWayToASignalThatIsHeard) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  feed(search, sim, 3);
  ASSERT_TRUE(search.target_signal().has_value());
  const std::uint32_t target = *search.target_signal();
  const double silence = quick().target_silence_s;
  for (int k = 3; k < 3 + static_cast<int>(silence) + 2; ++k) {
    ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.0, k * kSecond, (k + 1) * kSecond)).has_value());
    for (const auto& m : sim.measure((k + 1) * kSecond)) {
      if (m.signal_id != target) {
        ASSERT_TRUE(std::holds_alternative<SearchUpdate>(search.process(m)));
      }
    }
    if (k < 3 + static_cast<int>(silence) - 1) {
      EXPECT_EQ(search.target_signal(), target) << "still sticky at " << k;
    }
  }
  ASSERT_TRUE(search.target_signal().has_value());
  EXPECT_NE(*search.target_signal(), target) << "the silent target kept the rescuer";
}

// Victim A dug out and switched off while the rescuer stands over its converged estimate, the
// device hearing nothing at all: after lost_signal_steps quiet epochs the target is left (its
// transmitter is off), not walked to for ever; a pulse of it heard again makes it a target again.
TEST(RescuerSearch, AConvergedTargetFallenSilentUnderfootIsLeftAndTakenBackWhenHeard) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  const int epochs = 30;  // walking north 0.5 m an epoch: 0.5 m short of A at the end
  std::optional<FieldMeasurement> last_of_a;
  for (const auto& m : feed(search, sim, epochs))
    if (sim.victim_of_signal(m.signal_id) == 0U) last_of_a = m;
  ASSERT_TRUE(last_of_a.has_value());
  const std::uint32_t a = last_of_a->signal_id;
  ASSERT_EQ(search.target_signal(), a);
  ASSERT_GE(search.estimate(a)->status, EstimatorStatus::kConverged);
  ASSERT_TRUE(sim.switch_off_transmitter_near(s.victims[0].position, 3.0));
  ASSERT_TRUE(sim.switch_off_transmitter_near(s.victims[1].position, 3.0));
  const auto steps = static_cast<int>(quick().search.lost_signal_steps);
  TimestampNs t = (epochs + 1) * kSecond;
  for (int k = 0; k < steps; ++k, t += kSecond) {
    ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.0, t - kSecond, t)).has_value());
    ASSERT_TRUE(sim.measure(t).empty()) << "both transmitters are off";
    const auto g = search.coast(t);
    if (k + 1 < steps) {
      ASSERT_TRUE(g.has_value()) << k;
      EXPECT_EQ(g->signal_id, a) << "still A's after " << k + 1 << " quiet epochs";
      EXPECT_LT(g->distance_m, 2.0);
    } else {
      EXPECT_TRUE(!g || g->signal_id != a) << "A is left after " << steps << " quiet epochs";
    }
  }
  EXPECT_EQ(search.silenced_targets(), 1U);
  EXPECT_NE(search.target_signal(), a);
  // Heard again (on again, or another transmitter where it was): searched again.
  FieldMeasurement again = *last_of_a;
  again.stamp = t;
  again.sequence = last_of_a->sequence + 1000;
  ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.0, t - kSecond, t)).has_value());
  const auto out = search.process(again);
  ASSERT_TRUE(std::holds_alternative<SearchUpdate>(out));
  EXPECT_EQ(search.target_signal(), a);
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

// One rescuer per victim: a signal whose victim incident command sends another rescuer to is not
// guided to while handed over; lifted, or lapsed once a sample is stamped after `until` (a plan
// from a silent incident command), it is again.
TEST(RescuerSearch, SignalsLeftToOthersAreNotGuidedToUntilTheHandOverLiftsOrLapses) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  feed(search, sim, 4);
  ASSERT_TRUE(search.target_signal().has_value());
  const auto first = *search.target_signal();
  search.leave_to_others({first}, 60 * kSecond);
  ASSERT_TRUE(search.target_signal().has_value()) << "another victim is heard";
  const auto second = *search.target_signal();
  EXPECT_NE(second, first);
  search.leave_to_others({first, second}, 60 * kSecond);
  EXPECT_FALSE(search.target_signal().has_value());
  ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.5, 4 * kSecond, 5 * kSecond)).has_value());
  for (const auto& m : sim.measure(5 * kSecond)) {
    auto out = search.process(m);
    ASSERT_TRUE(std::holds_alternative<SearchUpdate>(out));
    EXPECT_FALSE(std::get<SearchUpdate>(out).guidance.has_value()) << "guided towards a victim handed over";
  }
  EXPECT_FALSE(search.target_signal().has_value());
  search.leave_to_others({}, 60 * kSecond);
  EXPECT_TRUE(search.target_signal().has_value()) << "lifted";
  search.leave_to_others({first, second}, 5 * kSecond);
  EXPECT_FALSE(search.target_signal().has_value());
  ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.5, 5 * kSecond, 6 * kSecond)).has_value());
  for (const auto& m : sim.measure(6 * kSecond)) (void)search.process(m);
  EXPECT_TRUE(search.target_signal().has_value()) << "lapsed: a sample after `until`";
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

TEST(RescuerSearch, CoastingFarFromWhereTheSignalWasLastHeardTurnsBack) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  feed(search, sim, 4);
  ASSERT_TRUE(search.target_signal().has_value());
  // Walk away, unheard, in the receiver's own x direction: 12 one-metre steps.
  TimestampNs t = 4 * kSecond;
  for (int k = 0; k < 12; ++k, t += kSecond)
    ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 1.0, t, t + kSecond)).has_value());
  const auto g = search.coast(t);
  ASSERT_TRUE(g.has_value());
  // More than search.coast_return_m (10 m) from the last sample: back where it was heard,
  // i.e. behind the receiver (bearing about 180 degrees), whatever the mixture says.
  EXPECT_GT(std::fabs(g->bearing_rad), 2.6);
  EXPECT_GT(g->step_m, 0.0);
}

TEST(RescuerSearch, FoundWitnessSettingsAreValidatedByName) {
  RescuerSearchConfig c;
  EXPECT_NO_THROW(c.validate());
  c.found_witness_window_s = -1.0;
  EXPECT_NE(sarloc::test::validation_error(c).find("rescuer_search.found_witness_window_s = -1"), std::string::npos)
      << sarloc::test::validation_error(c);
  c = RescuerSearchConfig{};
  c.found_witness_gate_probability = 1.0;
  EXPECT_THROW(c.validate(), ConfigError);
  c = RescuerSearchConfig{};
  c.found_witness_radius_factor = 0.5;  // a witness tighter than the FOUND itself: never
  EXPECT_NE(sarloc::test::validation_error(c).find("rescuer_search.found_witness_radius_factor = 0.5"),
            std::string::npos)
      << sarloc::test::validation_error(c);
  c = RescuerSearchConfig{};
  c.found_witness_window_s = 0.0;  // off
  EXPECT_NO_THROW(c.validate());
}

}  // namespace
}  // namespace sarloc::avalanche
