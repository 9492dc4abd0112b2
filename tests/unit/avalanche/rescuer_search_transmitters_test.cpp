// RescuerSearch with transmitters close together: one split into two signals is found once, two
// half a metre apart are both found.
#include "sarloc/core/avalanche/rescuer_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sarloc/core/mission/simulated_rescuer.hpp"
#include "rescuer_search_world.hpp"

namespace sarloc::avalanche {
namespace {

using test::feed;
using test::kSecond;
using test::quick;
using test::scenario;

// Walks the search as guided for up to `epochs`, each measurement passed through `edit` (which
// may add samples) and every outcome to `seen`. Stops early when `done` says so.
template <typename Edit, typename Seen, typename Done>
void guided_search(RescuerSearch& search, mission::SimulatedRescuer& sim, int epochs, Edit edit, Seen seen, Done done) {
  for (int k = 0; k < epochs && !done(); ++k) {
    const TimestampNs t = (k + 1) * kSecond;
    std::optional<Guidance> g;
    for (const auto& measured : sim.measure(t)) {
      for (const FieldMeasurement& m : edit(measured, k)) {
        auto outcome = search.process(m);
        ASSERT_TRUE(std::holds_alternative<SearchUpdate>(outcome));
        const auto& u = std::get<SearchUpdate>(outcome);
        if (u.guidance) g = u.guidance;
        seen(m, u);
      }
    }
    if (!g) g = search.coast(t);
    if (!g) return;
    ASSERT_FALSE(search.add_odometry(sim.walk(g->bearing_rad, g->step_m, t, t + kSecond)).has_value());
  }
}

// The live failure (four within 5 m): the separation split one transmitter into two signals, and
// both were found, one victim twice. The second signal (a copy of A's samples from after A was
// found) is suspected from its first claim, never published above kConverged, and, stood over, a
// confirmed repeat: the search moves on to B.
TEST(RescuerSearch, OneTransmitterSplitIntoTwoSignalsIsFoundOnce) {
  const auto s = scenario();
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  constexpr std::uint32_t kCopy = 100;
  std::optional<std::uint32_t> a_signal;
  std::optional<int> a_found_at;
  EstimatorStatus copy_highest = EstimatorStatus::kInitialising;
  std::optional<VictimEstimate> copy_last;
  std::optional<FieldMeasurement> a_last;
  int k_now = 0;
  guided_search(
      search, sim, 200,
      [&](const FieldMeasurement& m, int k) {
        k_now = k;
        std::vector<FieldMeasurement> out{m};
        if (sim.victim_of_signal(m.signal_id) == 0U) {
          a_signal = m.signal_id;
          a_last = m;
          if (a_found_at && k > *a_found_at) {
            FieldMeasurement copy = m;
            copy.signal_id = kCopy;
            out.push_back(copy);
          }
        }
        return out;
      },
      [&](const FieldMeasurement& m, const SearchUpdate& u) {
        if (!u.estimate) return;
        if (m.signal_id == a_signal && u.estimate->status == EstimatorStatus::kFound && !a_found_at) a_found_at = k_now;
        if (m.signal_id == kCopy) {
          copy_highest = std::max(copy_highest, u.estimate->status);
          copy_last = u.estimate;
        }
      },
      [&] { return copy_last && copy_last->repeat == responder::RepeatState::kConfirmed; });
  ASSERT_TRUE(a_found_at.has_value()) << "A is found";
  ASSERT_TRUE(copy_last.has_value()) << "the copy was tracked";
  EXPECT_EQ(copy_last->repeat, responder::RepeatState::kConfirmed);
  EXPECT_EQ(copy_last->repeat_of_signal, *a_signal);
  EXPECT_EQ(search.confirmed_repeats(), 1U);
  EXPECT_LE(copy_highest, EstimatorStatus::kConverged) << "a repeat never claims a victim";
  EXPECT_NE(search.target_signal(), std::optional<std::uint32_t>(kCopy)) << "the search moved on";
  EXPECT_NE(search.target_signal(), std::optional<std::uint32_t>(*a_signal));
  // The receiver's separation is told which signal the copy repeats (SignalSeparator
  // original_of_repeats), and that A repeats none.
  const auto copy_fit = search.field_fit(kCopy, a_last->field, a_last->noise_stddev, a_last->valid_axes);
  const auto a_fit = search.field_fit(*a_signal, a_last->field, a_last->noise_stddev, a_last->valid_axes);
  ASSERT_TRUE(copy_fit && a_fit);
  EXPECT_EQ(copy_fit->repeat_of, *a_signal);
  EXPECT_EQ(a_fit->repeat_of, 0U);
}

// Two transmitters half a metre apart are two victims: their moments differ, and each is found.
TEST(RescuerSearch, TwoTransmittersHalfAMetreApartAreBothFound) {
  auto s = scenario();
  s.victims.push_back({"A2", Vec3(0.5, 15.0, -1.2), Vec3(-0.004, 0.003, 0.015), {}, {}});
  mission::SimulatedRescuer sim(s, "r");
  RescuerSearch search("r", quick());
  std::set<std::size_t> found;
  guided_search(
      search, sim, 250, [](const FieldMeasurement& m, int) { return std::vector<FieldMeasurement>{m}; },
      [&](const FieldMeasurement& m, const SearchUpdate& u) {
        if (u.estimate && u.estimate->status == EstimatorStatus::kFound) found.insert(*sim.victim_of_signal(m.signal_id));
      },
      [&] { return found.count(0) != 0 && found.count(2) != 0; });
  EXPECT_EQ(found.count(0), 1U) << "A found";
  EXPECT_EQ(found.count(2), 1U) << "A2, 0.5 m from A, found too";
  EXPECT_EQ(search.confirmed_repeats(), 0U);
}

}  // namespace
}  // namespace sarloc::avalanche

namespace sarloc::avalanche {
namespace {

// The lost-signal re-plan (search.lost_signal_steps) walks the primary line again only when the
// device hears nothing at all: a target silent beside a found victim still heard every epoch is
// masked, not out of range (sweeping away from a cluster cost multiple burials their misses).
TEST(RescuerSearchLostSignal, TheLineIsWalkedAgainOnlyWhenNoSignalAtAllIsHeard) {
  mission::SimulatedRescuer sim(test::scenario(), "r");
  RescuerSearchConfig config = test::quick();
  ASSERT_GT(config.search.lost_signal_steps, 0U) << "shipped on";
  RescuerSearch search("r", config);
  const std::vector<FieldMeasurement> first = test::feed(search, sim, 1);
  ASSERT_EQ(first.size(), 2U);
  const std::uint32_t target = *search.target_signal();
  const std::uint32_t other = first[0].signal_id == target ? first[1].signal_id : first[0].signal_id;
  search.mark_done(other);  // found: heard, never guided to
  const auto wide = search.estimate(target);
  ASSERT_TRUE(wide);
  ASSERT_GT(radius95_3d(wide->relative.covariance), config.sog.converged_radius_m) << "a wide ring";
  auto epoch = [&](int k, bool other_heard) {
    const TimestampNs t = (k + 1) * test::kSecond;
    ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.5, t - test::kSecond, t)).has_value());
    for (FieldMeasurement m : sim.measure(t)) {
      if (m.signal_id == target || !other_heard) {
        m.valid_axes = 0;  // a pulse due and not heard
        m.field = Vec3::Zero();
      }
      ASSERT_TRUE(std::holds_alternative<SearchUpdate>(search.process(m))) << "epoch " << k;
    }
  };
  const int quiet = static_cast<int>(config.search.lost_signal_steps);
  int k = 1;
  for (; k < 1 + 3 * quiet; ++k) epoch(k, true);
  EXPECT_EQ(search.target_signal(), target);
  EXPECT_EQ(search.line_resumptions(), 0U) << "the found neighbour is heard: the target is masked";
  for (int n = 1; n < quiet; ++n, ++k) epoch(k, false);
  EXPECT_EQ(search.line_resumptions(), 0U) << "not yet quiet long enough";
  epoch(k++, false);
  EXPECT_EQ(search.line_resumptions(), 1U) << "nothing heard for lost_signal_steps epochs";
}

// A signal searched after another's victim opens along the primary search's line, not wherever
// the previous search left the rescuer facing (seen live: a third victim 26 m ahead of the first
// two unfound in 300 s, the rescuers walking off east and south from the second).
TEST(RescuerSearchPrimaryLine, ASignalSearchedAfterAnotherOpensAlongThePrimaryLine) {
  mission::SimulatedRescuer sim(test::scenario(), "r");
  RescuerSearch search("r", test::quick());
  const std::vector<FieldMeasurement> first = test::feed(search, sim, 1);  // walking north
  ASSERT_EQ(first.size(), 2U);
  const std::uint32_t target = *search.target_signal();
  const std::uint32_t other = first[0].signal_id == target ? first[1].signal_id : first[0].signal_id;
  // The first search turns him round (its fine search could leave him facing anywhere).
  for (int k = 1; k <= 3; ++k) {
    const TimestampNs t = (k + 1) * test::kSecond;
    ASSERT_FALSE(search.add_odometry(sim.walk(k == 1 ? kPi : 0.0, 0.5, t - test::kSecond, t)).has_value());
    for (const FieldMeasurement& m : sim.measure(t))
      ASSERT_TRUE(std::holds_alternative<SearchUpdate>(search.process(m)));
  }
  search.mark_done(target);  // found
  ASSERT_EQ(search.target_signal(), other);
  const TimestampNs t = 5 * test::kSecond;
  ASSERT_FALSE(search.add_odometry(sim.walk(0.0, 0.5, t - test::kSecond, t)).has_value());
  std::optional<Guidance> g;
  for (const FieldMeasurement& m : sim.measure(t)) {
    auto outcome = search.process(m);
    ASSERT_TRUE(std::holds_alternative<SearchUpdate>(outcome));
    if (std::get<SearchUpdate>(outcome).guidance) g = std::get<SearchUpdate>(outcome).guidance;
  }
  ASSERT_TRUE(g) << "the other signal heard and guided to";
  ASSERT_EQ(g->mode, GuidanceMode::kOpening) << "still a wide ring";
  EXPECT_GT(std::abs(g->bearing_rad), 0.9 * kPi) << "he faces south: the primary line (north) is behind him";
  // Walked on that way, he stays on it (no dithering on attitude noise).
  ASSERT_FALSE(search.add_odometry(sim.walk(g->bearing_rad, g->step_m, t, t + test::kSecond)).has_value());
  for (const FieldMeasurement& m : sim.measure(t + test::kSecond)) {
    auto outcome = search.process(m);
    ASSERT_TRUE(std::holds_alternative<SearchUpdate>(outcome));
    const auto& next = std::get<SearchUpdate>(outcome).guidance;
    if (next && next->mode == GuidanceMode::kOpening) {
      EXPECT_EQ(next->bearing_rad, 0.0);
    }
  }
}

}  // namespace
}  // namespace sarloc::avalanche
