// The search controller's decisions: its config, the LOCATED and FOUND criteria and the
// evidence they weigh, the bearing, confirmations beside the estimate, the located radius.
#include "sarloc/core/avalanche/search_controller.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "sarloc/core/avalanche/bearing_density.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "search_scenarios.hpp"
#include "support/config_messages.hpp"

namespace sarloc::avalanche {
namespace {

using test::victim_15_m_away;

TEST(SearchConfigTest, ValidatesWithKeyAndValue) {
  EXPECT_NO_THROW(SearchConfig{}.validate());
  SearchConfig c;
  c.located_radius_m = 0.0;
  EXPECT_NE(sarloc::test::validation_error(c).find("search.located_radius_m = 0"), std::string::npos)
      << sarloc::test::validation_error(c);
}

TEST(SearchControllerTest, AssessAppliesLocatedAndFoundCriteria) {
  SearchController ctl;
  VictimEstimate e;
  e.status = EstimatorStatus::kConverged;
  e.relative.position = Vec3(3.0, 0.0, -2.0);
  e.relative.covariance = Mat3::Identity() * 0.01;  // 95 % radius 0.28 m
  EXPECT_EQ(ctl.assess(e, {100}), EstimatorStatus::kLocated);
  e.relative.position = Vec3(0.2, 0.1, -2.0);
  EXPECT_EQ(ctl.assess(e, {100}), EstimatorStatus::kFound);
  e.relative.covariance = Mat3::Identity() * 0.1;  // 95 % radius 0.88 m
  EXPECT_EQ(ctl.assess(e, {100}), EstimatorStatus::kConverged);
  EXPECT_NEAR(radius95_3d(Mat3::Identity()), std::sqrt(7.814727903), 1e-6);
}

// Converged 2 m under the rescuer with a 0.28 m 95 % radius: found, if the evidence allows.
VictimEstimate tight_estimate_under_the_rescuer() {
  VictimEstimate e;
  e.status = EstimatorStatus::kConverged;
  e.relative.position = Vec3(0.2, 0.1, -2.0);
  e.relative.covariance = Mat3::Identity() * 0.01;
  return e;
}

// A filter whose latest samples alone allow the victim farther than twice the located radius
// (SogFilter::window_reaches) is neither LOCATED nor FOUND, however tight its own radius.
TEST(SearchControllerTest, LatestSamplesThatReachFartherConfirmNothing) {
  const SearchController ctl;
  const VictimEstimate e = tight_estimate_under_the_rescuer();
  ConfirmationEvidence evidence{100};
  EXPECT_EQ(ctl.assess(e, evidence), EstimatorStatus::kFound);
  evidence.window_reaches_farther = true;
  EXPECT_EQ(ctl.assess(e, evidence), EstimatorStatus::kConverged);
}

// A filter whose last six samples fit but whose longer history does not (it lost its transmitter
// while converged, and crept off) confirms nothing.
TEST(SearchControllerTest, AnInconsistentHistoryConfirmsNothing) {
  SearchController ctl;
  const VictimEstimate e = tight_estimate_under_the_rescuer();
  const double gate = ctl.config().confirm_max_innovation_ratio;
  EXPECT_EQ(ctl.assess(e, {100, 0.5 * gate, 1.0, true, 0.99 * gate}), EstimatorStatus::kFound);
  EXPECT_EQ(ctl.assess(e, {100, 0.5 * gate, 1.0, true, 1.01 * gate}), EstimatorStatus::kConverged);
  // Nor one whose probe samples, taken where it claimed to be precise, do not fit it.
  const double probe_gate = ctl.config().confirm_probe_gate_probability;
  EXPECT_EQ(ctl.assess(e, {100, 0.5 * gate, 1.0, true, 0.5 * gate, probe_gate - 1e-4}), EstimatorStatus::kFound);
  EXPECT_EQ(ctl.assess(e, {100, 0.5 * gate, 1.0, true, 0.5 * gate, probe_gate + 1e-4}), EstimatorStatus::kConverged);
}

// The probe samples are those taken while the estimate was within its located radius (there):
// a filter walked onto a transmitter and then fed a transmitter 1.5 m away has probe samples
// that do not fit it, and its evidence says so; its own transmitter's do fit.
TEST(SearchControllerTest, ProbeSamplesOfAnotherTransmitterAreEvidenceAgainstConfirming) {
  SearchController ctl;
  double own = 0.0, other = 0.0;
  for (const bool switched : {false, true}) {
    Scenario s;
    s.transmitter = Vec3(4.0, 3.0, -1.5);
    s.moment = Vec3(0.01, -0.005, 0.012);
    s.receiver = Vec3(0.0, 0.0, 1.0);
    AvalancheSimulator sim(SimulationConfig{}, s, 5);
    Scenario moved = s;
    moved.transmitter += Vec3(1.0, -1.0, -0.5);
    AvalancheSimulator elsewhere(SimulationConfig{}, moved, 6);
    SogConfig cfg;
    cfg.initial_components = 500;
    cfg.divergence_window = 0;  // no rebuild: what would the confirmation see?
    cfg.reinit_after = 0;
    cfg.leap_gate_probability = 0.0;
    SogFilter f(cfg);
    f.process(sim.measure());
    for (int k = 0; k < 40; ++k) {
      const Vec3 rel = sim.true_relative_position();
      const double bearing = std::atan2(rel.y(), rel.x()) - sim.scenario().receiver_rpy.z();
      const double step = std::min(0.5, rel.head<2>().norm());
      f.add_odometry(sim.walk(bearing + (k % 2 == 0 ? 0.8 : -0.8), step));
      elsewhere.walk(bearing + (k % 2 == 0 ? 0.8 : -0.8), step);
      FieldMeasurement z = switched && k >= 25 ? elsewhere.measure() : sim.measure();
      z.sequence = 100 + k;
      f.process(z);
    }
    const Vec3 at = f.moments().mean.segment<3>(idx::kPos);
    (switched ? other : own) = ctl.evidence(f, at).probe_nis_probability;
  }
  EXPECT_GT(own, 0.0) << "the walk took probe samples";
  EXPECT_LE(own, ctl.config().confirm_probe_gate_probability);
  EXPECT_GT(other, ctl.config().confirm_probe_gate_probability) << "own " << own;
}

// A filter of a few samples is a guess, however tight it looks: never located, never found.
// Nor is one whose newest sample does not fit, or whose moment the standard does not allow.
TEST(SearchControllerTest, WeakEvidenceConfirmsNothing) {
  SearchController ctl;
  const VictimEstimate e = tight_estimate_under_the_rescuer();
  const auto enough = static_cast<std::uint64_t>(ctl.config().confirm_min_samples);
  EXPECT_EQ(ctl.assess(e, {enough - 1}), EstimatorStatus::kConverged);
  EXPECT_EQ(ctl.assess(e, {enough}), EstimatorStatus::kFound);
  // Recent samples that do not fit the filter: its estimate is not confirmed either.
  const double gate = ctl.config().confirm_max_innovation_ratio;
  EXPECT_EQ(ctl.assess(e, {enough, 1.01 * gate}), EstimatorStatus::kConverged);
  EXPECT_EQ(ctl.assess(e, {enough, 0.99 * gate}), EstimatorStatus::kFound);
  // The newest sample does not fit, or the moment is not one the standard allows.
  const double last_gate = ctl.config().confirm_max_last_nis;
  EXPECT_EQ(ctl.assess(e, {enough, 0.0, 1.01 * last_gate}), EstimatorStatus::kConverged);
  EXPECT_EQ(ctl.assess(e, {enough, 0.0, 0.99 * last_gate}), EstimatorStatus::kFound);
  EXPECT_EQ(ctl.assess(e, {enough, 0.0, 0.0, false}), EstimatorStatus::kConverged);
}

// An estimate above the receiver is a filter's mirror solution (H(r) = H(-r)), not a victim:
// never located or found, however small its covariance or large its range.
TEST(SearchControllerTest, AnEstimateAboveTheReceiverIsNeverLocated) {
  SearchController ctl;
  VictimEstimate e;
  e.status = EstimatorStatus::kConverged;
  e.relative.covariance = Mat3::Identity() * 0.01;
  e.relative.position = Vec3(0.1, 0.1, 30.0);  // straight up: "found" by radius and distance
  EXPECT_EQ(ctl.assess(e, {100}), EstimatorStatus::kConverged);
  e.relative.position = Vec3(0.1, 0.1, -0.1);  // below, but not by 2 sigma (0.2 m)
  EXPECT_EQ(ctl.assess(e, {100}), EstimatorStatus::kConverged);
  e.relative.position = Vec3(0.1, 0.1, -1.5);
  EXPECT_EQ(ctl.assess(e, {100}), EstimatorStatus::kFound);
  e.status = EstimatorStatus::kMultimodal;
  e.relative.position = Vec3(0.1, 0.1, 3.0);
  EXPECT_EQ(ctl.assess(e, {100}), EstimatorStatus::kMultimodal) << "never raised";
}

// A transmitter 32 m away, the receiver facing away from it: the real loop walks it down.
Scenario walk_scenario() {
  Scenario s;
  s.transmitter = Vec3(-20.0, 25.0, -1.0);
  s.moment = Vec3(0.0, 0.015, 0.01);
  s.receiver = Vec3(0, 0, 1);
  s.receiver_rpy = Vec3(0, 0, -2.0);
  return s;
}

TEST(SearchControllerTest, BearingIsRelativeToReceiverForwardAxis) {
  // A converged filter: walk the real loop until the controller leaves the flux line, then
  // the bearing must point the receiver at the estimate.
  AvalancheSimulator sim(SimulationConfig{}, walk_scenario(), 21);
  SogConfig cfg;
  cfg.initial_components = 500;
  SogFilter f(cfg);
  SearchController ctl;
  Guidance g;
  int approach_steps = 0;
  for (int k = 0; k < 60; ++k) {
    const FieldMeasurement z = sim.measure();
    f.process(z);
    g = ctl.guide(f, z);
    if (g.mode == GuidanceMode::kApproach) {
      ++approach_steps;
      const double yaw = f.moments().mean[idx::kAtt + 2];
      EXPECT_NEAR(wrap_angle(g.bearing_rad + yaw - g.heading_rad), 0.0, 1e-9);
      const Vec3 mean = f.estimate().relative.position;
      EXPECT_NEAR(wrap_angle(g.heading_rad - std::atan2(mean.y(), mean.x())), 0.0, 1e-9);
      EXPECT_DOUBLE_EQ(g.step_m, 1.0);
    }
    if (g.mode == GuidanceMode::kFound) break;
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  EXPECT_GT(approach_steps, 5);
  EXPECT_EQ(g.mode, GuidanceMode::kFound);
  EXPECT_DOUBLE_EQ(g.step_m, 0.0);
  EXPECT_LT(sim.true_horizontal_distance(), 1.0);
}


// FOUND needs found_confirmations samples in a row that say so, taken beside the estimate:
// with 3 the real loop ends at least 2 steps after it would with 1, after fine-search probes
// that keep the rescuer near the transmitter.
TEST(SearchControllerTest, FoundNeedsConfirmationsInARowBesideTheEstimate) {
  auto run = [](std::uint32_t confirmations, std::vector<Guidance>* trace) {
    AvalancheSimulator sim(SimulationConfig{}, walk_scenario(), 21);
    SogConfig cfg;
    cfg.initial_components = 500;
    SogFilter f(cfg);
    SearchConfig sc;
    sc.found_confirmations = confirmations;
    SearchController ctl(sc);
    for (int k = 0; k < 80; ++k) {
      const FieldMeasurement z = sim.measure();
      f.process(z);
      const Guidance g = ctl.guide(f, z);
      trace->push_back(g);
      if (g.mode == GuidanceMode::kFound) return std::pair<int, double>(k, sim.true_horizontal_distance());
      f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
    }
    return std::pair<int, double>(-1, sim.true_horizontal_distance());
  };
  std::vector<Guidance> once, thrice;
  const auto [k1, d1] = run(1, &once);
  const auto [k3, d3] = run(3, &thrice);
  ASSERT_GE(k1, 0);
  ASSERT_GE(k3, 0);
  EXPECT_GE(k3, k1 + 2);
  EXPECT_LT(d3, 1.0);
  // The two samples before the FOUND were probes beside the estimate, not a stand-still.
  for (int k = k3 - 2; k < k3; ++k) {
    EXPECT_EQ(thrice[k].mode, GuidanceMode::kFineSearch) << "step " << k;
    EXPECT_GT(thrice[k].step_m, 0.0) << "step " << k;
  }
}

// A signal heard only every `every`-th epoch (its pulses lost under other transmitters' in
// between): the rescuer coasts between samples. Found within `max_epochs`, 0.5 m of the truth;
// the samples that confirm the FOUND after the first one were taken beside the estimate, not on
// it, because coasting waits on the probe point: as long as the signal's gaps have been (3 to 30
// epochs), then no longer (a signal not heard there must not hold the rescuer for ever).
void expect_a_sparse_signal_confirmed_beside_the_estimate(int every, int max_epochs) {
  const Scenario s = victim_15_m_away();
  AvalancheSimulator sim(SimulationConfig{}, s, 6);
  SogConfig cfg;
  cfg.initial_components = 500;
  SogFilter f(cfg);
  SearchController ctl;
  const int patience = std::max(3, every - 1);  // epochs coasted between two samples
  std::vector<double> guided_distance;          // rescuer to estimate at each guided sample
  bool found = false;
  int waits_seen = 0;
  for (int step = 0; step < max_epochs && !found; ++step) {
    Guidance g;
    if (step % every == 0) {
      const FieldMeasurement z = sim.measure();
      f.process(z);
      g = ctl.guide(f, z);
      guided_distance.push_back(g.distance_m);
      found = g.mode == GuidanceMode::kFound;
      SearchController waiting = ctl;
      if (!found && step > 0 && waiting.coast(f).step_m == 0.0) {
        ++waits_seen;
        for (int k = 2; k <= patience; ++k) EXPECT_EQ(waiting.coast(f).step_m, 0.0) << "left the probe point after " << k;
        EXPECT_GT(waiting.coast(f).step_m, 0.0) << "still waiting after " << patience << " epochs";
      }
    } else {
      g = ctl.coast(f);
    }
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  ASSERT_TRUE(found) << "heard every " << every << " epochs: never confirmed in " << max_epochs;
  const auto n = static_cast<std::size_t>(ctl.config().found_confirmations);
  ASSERT_GE(guided_distance.size(), n);
  for (std::size_t i = guided_distance.size() - n + 1; i < guided_distance.size(); ++i)
    EXPECT_GE(guided_distance[i], 0.5 * ctl.config().found_distance_m) << "confirming sample " << i;
  EXPECT_GE(waits_seen, 1);
  EXPECT_LT((f.estimate(0).relative.position - sim.true_relative_position()).norm(), 0.5);
}

// Every third epoch. Before, coasting walked back onto the estimate and three samples from one
// spot confirmed a ghost.
TEST(SearchControllerTest, ConfirmingSamplesOfASparseSignalAreTakenBesideTheEstimate) {
  expect_a_sparse_signal_confirmed_beside_the_estimate(3, 400);
}

// Every seventh epoch (seen: a victim 0.2 m deep whose pulses were lost under a carrier-mate's six
// times in seven). Waiting three epochs on a probe point, the rescuer was back on the estimate
// whenever the next sample came, and never confirmed the FOUND (750 s, 4 victims seed 1 trial 48;
// here: never in 600 epochs).
TEST(SearchControllerTest, ARarelyHeardSignalIsWaitedForOnTheProbePoint) {
  expect_a_sparse_signal_confirmed_beside_the_estimate(7, 600);
}

// Every fifteenth epoch (seen: victims located 0.03-0.1 m off, heard once in 10-20 epochs under a
// neighbour 5-13 Hz away; the rescuer left each probe point after 10, search.confirm_max_waits
// then, and they were never confirmed in 800 epochs: 4 victims, seed 10 trial 9, seed 13 trial 96).
TEST(SearchControllerTest, ASignalHeardOnceInFifteenEpochsIsWaitedForOnTheProbePoint) {
  expect_a_sparse_signal_confirmed_beside_the_estimate(15, 1500);
}

// A deep victim: the confirming samples are taken confirm_probe_per_depth times its depth below
// the antenna beside the estimate, not found_distance_m. 0.5 m beside a victim 3.9 m down barely
// changes the field (seen: a FOUND 0.99 m off with a 0.44 m radius).
TEST(SearchControllerTest, ConfirmingSamplesOfADeepVictimAreTakenFurtherBeside) {
  auto confirming_distances = [](double per_depth) {
    Scenario s;
    s.transmitter = Vec3(6.0, -4.0, -2.9);
    s.moment = Vec3(0.006, -0.008, 0.004);
    s.receiver = Vec3(0, 0, 1);
    AvalancheSimulator sim(SimulationConfig{}, s, 11);
    SogConfig cfg;
    cfg.initial_components = 500;
    SogFilter f(cfg);
    SearchConfig sc;
    sc.confirm_probe_per_depth = per_depth;
    SearchController ctl(sc);
    std::vector<double> guided;
    for (int k = 0; k < 300; ++k) {
      const FieldMeasurement z = sim.measure();
      f.process(z);
      const Guidance g = ctl.guide(f, z);
      guided.push_back(g.distance_m);
      if (g.mode == GuidanceMode::kFound) {
        const Vec3 error = f.estimate(0).relative.position - sim.true_relative_position();
        EXPECT_LT(error.norm(), 0.5) << "per_depth " << per_depth;
        // The samples after the first that said "found" were taken beside the estimate.
        return std::vector<double>(guided.end() - static_cast<std::ptrdiff_t>(sc.found_confirmations) + 1, guided.end());
      }
      f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
    }
    ADD_FAILURE() << "not found, per_depth " << per_depth;
    return std::vector<double>{};
  };
  const std::vector<double> near = confirming_distances(0.0);
  const std::vector<double> far = confirming_distances(0.35);
  ASSERT_FALSE(near.empty());
  ASSERT_FALSE(far.empty());
  const double depth_below_antenna = 3.9;
  for (double d : near) EXPECT_LE(d, 2.0 * SearchConfig{}.found_distance_m);
  for (double d : far) EXPECT_GE(d, 0.5 * 0.35 * depth_below_antenna * 0.8);  // the estimate's depth, not the truth's
  EXPECT_GT(*std::min_element(far.begin(), far.end()), *std::max_element(near.begin(), near.end()));
}

// Precision scales with range, so "located" does too: a deep burial is located at a radius a
// shallow one is not (a fixed radius left a 5.6 m burial unfound for 150 steps).
TEST(SearchControllerLocated, RadiusScalesWithRangeAboveTheNearRangeFloor) {
  SearchController controller;  // defaults: 0.4 m floor, 10 % of range
  VictimEstimate e;
  e.status = EstimatorStatus::kConverged;
  // A 95 % 3-D radius of 0.48 m: sqrt(chi2_3(0.95) * sigma^2) = 0.48 -> sigma^2 = 0.48^2 / 7.815.
  e.relative.covariance = Mat3::Identity() * (0.48 * 0.48 / 7.8147);
  ASSERT_NEAR(radius95_3d(e.relative.covariance), 0.48, 1e-3);

  e.relative.position = Vec3(1.5, 0.0, -2.0);  // 2.5 m away: the 0.4 m floor applies
  EXPECT_EQ(controller.assess(e, {100}), EstimatorStatus::kConverged);
  e.relative.position = Vec3(1.5, 0.0, -6.6);  // 6.8 m away: 10 % of it is 0.68 m
  EXPECT_EQ(controller.assess(e, {100}), EstimatorStatus::kLocated);
  e.relative.position = Vec3(0.2, 0.0, -6.6);  // on top of it
  EXPECT_EQ(controller.assess(e, {100}), EstimatorStatus::kFound);

  SearchConfig fixed;
  fixed.located_radius_per_range = 0.0;
  EXPECT_EQ(SearchController(fixed).assess(e, {100}), EstimatorStatus::kConverged);
  fixed.located_radius_per_range = 1.5;
  EXPECT_THROW(fixed.validate(), ConfigError);
}

// ... but never beyond located_radius_max_m: far off, a radius of 10 % of the range is a guess,
// not a place to dig (seen live: LOCATED 39 m away with a 3.9 m radius, 29 m from any victim).
TEST(SearchControllerLocated, NoFarEstimateIsLocatedWithARadiusAboveTheCap) {
  VictimEstimate e;
  e.status = EstimatorStatus::kConverged;
  e.relative.covariance = Mat3::Identity() * (3.5 * 3.5 / 7.8147);  // a 95 % radius of 3.5 m
  e.relative.position = Vec3(38.0, 0.0, -9.0);                      // 39 m away
  EXPECT_EQ(SearchController().assess(e, {100}), EstimatorStatus::kConverged);
  SearchConfig uncapped;
  uncapped.located_radius_max_m = 50.0;
  EXPECT_EQ(SearchController(uncapped).assess(e, {100}), EstimatorStatus::kLocated) << "the cap decides it";
  // 14 m away with a 0.95 m radius is located: within the cap and 10 % of the range.
  e.relative.covariance = Mat3::Identity() * (0.95 * 0.95 / 7.8147);
  e.relative.position = Vec3(13.0, 0.0, -5.0);
  EXPECT_EQ(SearchController().assess(e, {100}), EstimatorStatus::kLocated);
  SearchConfig inverted;
  inverted.located_radius_max_m = 0.3;  // under located_radius_m
  EXPECT_THROW(inverted.validate(), ConfigError);
}

}  // namespace
}  // namespace sarloc::avalanche
