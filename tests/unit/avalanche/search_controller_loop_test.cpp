// The search controller in its loop: the adaptive end (a stalled search ends with a probe
// pattern), the opening heading, and the lost-signal re-plan.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "sarloc/core/avalanche/bearing_density.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/avalanche/search_controller.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "search_scenarios.hpp"
#include "support/config_messages.hpp"

namespace sarloc::avalanche {
namespace {

using test::victim_15_m_away;

// The search loop of the evaluation on one scenario (default noise, a victim 15 m away), until
// kFound or the budget: what the adaptive end did.
struct SearchRun {
  bool found = false;
  int steps = 0;
  double error_m = 0.0;              ///< |estimate - truth| (3-D) at the end
  double radius95_m = 0.0;           ///< stated with the final estimate
  double final_distance_m = 0.0;     ///< rescuer to victim, horizontal, at the end
  bool by_probe_pattern = false;
  std::size_t pattern_size = 0;
  std::size_t pattern_visited = 0;
  int fine_steps_before_pattern = 0; ///< consecutive fine-search steps before it was laid out
  int steps_walking_pattern = 0;     ///< steps from its layout to the end
  std::vector<double> fine_radius95; ///< 95 % radius of each fine-search step before the layout
};

SearchRun run_search(const SearchConfig& sc, int budget, SearchController* end_state = nullptr) {
  const Scenario s = victim_15_m_away();
  AvalancheSimulator sim(SimulationConfig{}, s, 4);
  SogConfig cfg;
  cfg.initial_components = 500;
  SogFilter f(cfg);
  SearchController ctl(sc);
  SearchRun run;
  int fine_steps = 0;
  for (run.steps = 1; run.steps <= budget; ++run.steps) {
    const FieldMeasurement z = sim.measure();
    f.process(z);
    const bool had_pattern = !ctl.probe_pattern().empty();
    const Guidance g = ctl.guide(f, z);
    const VictimEstimate e = f.estimate(0);
    run.error_m = (e.relative.position - sim.true_relative_position()).norm();
    run.radius95_m = radius95_3d(e.relative.covariance);
    run.final_distance_m = sim.true_horizontal_distance();
    if (!had_pattern && !ctl.probe_pattern().empty()) run.fine_steps_before_pattern = fine_steps + 1;
    if (!ctl.probe_pattern().empty()) ++run.steps_walking_pattern;
    fine_steps = g.mode == GuidanceMode::kFineSearch ? fine_steps + 1 : 0;
    if (!had_pattern && g.mode == GuidanceMode::kFineSearch) {
      if (fine_steps == 1) run.fine_radius95.clear();
      run.fine_radius95.push_back(run.radius95_m);
    }
    if (g.mode == GuidanceMode::kFound) {
      EXPECT_DOUBLE_EQ(g.step_m, 0.0);
      run.found = true;
      break;
    }
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  run.by_probe_pattern = ctl.found_by_probe_pattern();
  run.pattern_size = ctl.probe_pattern().size();
  run.pattern_visited = ctl.probe_points_visited();
  if (end_state != nullptr) *end_state = ctl;
  return run;
}

// A located radius the data cannot reach (2 cm) stands for noisier sensors than the
// defaults: without the adaptive end the rescuer stands on the estimate and probes until the
// budget runs out; with it, the search ends after the stall window and a complete probe
// pattern, and the FOUND is honest (the victim within the stated 95 % radius + 0.5 m).
TEST(SearchControllerAdaptiveEnd, EndsAStalledSearchWithAProbePattern) {
  SearchConfig unreachable;
  unreachable.located_radius_m = 0.02;
  unreachable.located_radius_per_range = 0.0;
  SearchConfig off = unreachable;
  off.stall_window_steps = 0;
  const SearchRun stuck = run_search(off, 120);
  EXPECT_FALSE(stuck.found);
  EXPECT_LT(stuck.final_distance_m, 1.0) << "the rescuer stood on the victim all along";
  EXPECT_LT(stuck.error_m, 0.5) << "with a good estimate";

  const SearchRun ended = run_search(unreachable, 120);
  ASSERT_TRUE(ended.found);
  EXPECT_TRUE(ended.by_probe_pattern);
  ASSERT_GE(ended.pattern_size, 1u);
  EXPECT_EQ(ended.pattern_visited, ended.pattern_size) << "every probe point walked";
  EXPECT_GE(ended.steps_walking_pattern, static_cast<int>(ended.pattern_size));
  EXPECT_LE(ended.error_m, ended.radius95_m + 0.5);
  EXPECT_LT(ended.steps, 100);
  // Not ended while still improving: the pattern was laid out after a full window of
  // fine-search steps none of which undercut the earlier best by stall_min_improvement.
  const int w = unreachable.stall_window_steps;
  const auto& r = ended.fine_radius95;
  ASSERT_EQ(static_cast<int>(r.size()), ended.fine_steps_before_pattern);
  ASSERT_GT(static_cast<int>(r.size()), w);
  const double best_before = *std::min_element(r.begin(), r.end() - w);
  const double best_in_window = *std::min_element(r.end() - w, r.end());
  EXPECT_GE(best_in_window, (1.0 - unreachable.stall_min_improvement) * best_before);
}

// A complete pattern stands for the estimate it was laid out for only. The same controller then
// guided by a mixture many metres wide (its filter rebuilt, confirmable all the same: enough
// samples, innovations within their gates, a plausible moment) says nothing is found there.
TEST(SearchControllerAdaptiveEnd, ACompletePatternSaysNothingOfAWiderEstimate) {
  SearchConfig unreachable;
  unreachable.located_radius_m = 0.02;
  unreachable.located_radius_per_range = 0.0;
  SearchController ctl(unreachable);
  ASSERT_TRUE(run_search(unreachable, 120, &ctl).by_probe_pattern);
  Scenario far;
  far.transmitter = Vec3(30.0, 25.0, -1.5);
  far.moment = Vec3(0.01, 0.004, -0.006);
  far.receiver = Vec3(0, 0, 1);
  AvalancheSimulator sim(SimulationConfig{}, far, 8);
  SogConfig cfg;
  cfg.initial_components = 500;
  SogFilter wide(cfg);
  for (int k = 0; k < 12; ++k) wide.process(sim.measure());
  ASSERT_TRUE(ctl.confirmable(ctl.evidence(wide, wide.moments().mean.segment<3>(idx::kPos))));
  ASSERT_GT(radius95_3d(wide.moments().covariance.block<3, 3>(idx::kPos, idx::kPos)), 5.0);
  for (int k = 0; k < 5; ++k) {
    const FieldMeasurement z = sim.measure();
    wide.process(z);
    EXPECT_NE(ctl.guide(wide, z).mode, GuidanceMode::kFound) << "sample " << k;
  }
  EXPECT_FALSE(ctl.found_by_probe_pattern());
}

// A probe pattern walked for a signal heard every third epoch: each point counts only with a
// sample taken on it (coast() waits there), so the samples of the pattern come from its points,
// not all from the estimate the rescuer coasted back to between samples.
TEST(SearchControllerAdaptiveEnd, APatternOfASparseSignalIsSampledOnItsPoints) {
  SearchConfig unreachable;
  unreachable.located_radius_m = 0.02;
  unreachable.located_radius_per_range = 0.0;
  unreachable.found_distance_m = 0.1;  // a pattern of several points over the 95 % region
  const Scenario s = victim_15_m_away();
  AvalancheSimulator sim(SimulationConfig{}, s, 4);
  SogConfig cfg;
  cfg.initial_components = 500;
  SogFilter f(cfg);
  SearchController ctl(unreachable);
  std::vector<double> off_estimate;  // rescuer to estimate at each sample of the pattern walk
  bool found = false;
  for (int step = 0; step < 600 && !found; ++step) {
    Guidance g;
    if (step % 3 == 0) {
      const FieldMeasurement z = sim.measure();
      f.process(z);
      const bool walking = !ctl.probe_pattern().empty();
      g = ctl.guide(f, z);
      found = g.mode == GuidanceMode::kFound;
      if (walking && !found) off_estimate.push_back(g.distance_m);
    } else {
      g = ctl.coast(f);
    }
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  ASSERT_TRUE(found);
  ASSERT_TRUE(ctl.found_by_probe_pattern());
  ASSERT_GE(ctl.probe_pattern().size(), 3U);
  // Its points lie around the estimate: most samples are taken off it. Coasting back onto the
  // estimate between samples took every one there.
  const auto off = std::count_if(off_estimate.begin(), off_estimate.end(),
                                 [&](double d) { return d >= 0.5 * unreachable.found_distance_m; });
  EXPECT_GE(2 * off, static_cast<long>(off_estimate.size())) << off << " of " << off_estimate.size() << " samples off the estimate";
}

TEST(SearchControllerAdaptiveEnd, ConfigIsValidated) {
  SearchConfig c;
  c.stall_window_steps = -1;
  EXPECT_NE(sarloc::test::validation_error(c).find("search.stall_window_steps = -1"), std::string::npos)
      << sarloc::test::validation_error(c);
  c = SearchConfig{};
  c.stall_min_improvement = 0.9;
  EXPECT_THROW(c.validate(), ConfigError);
}

TEST(SearchControllerOpening, ParsesHeadingSourceAndNamesABadOne) {
  EXPECT_EQ(parse_opening_heading("flux_line"), OpeningHeading::kFluxLine);
  EXPECT_EQ(parse_opening_heading("lookahead"), OpeningHeading::kLookahead);
  EXPECT_EQ(parse_opening_heading(to_string(OpeningHeading::kLookahead)), OpeningHeading::kLookahead);
  EXPECT_EQ(parse_opening_heading(to_string(OpeningHeading::kPosteriorBearing)),
            OpeningHeading::kPosteriorBearing);
  try {
    parse_opening_heading("north");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("search.opening_heading = 'north'"), std::string::npos);
  }
  SearchConfig c;
  c.bearing_switch_ratio = 0.5;  // < 1 would turn towards a less probable bearing
  EXPECT_THROW(c.validate(), ConfigError);
}

// The opening heading is the most probable bearing of the mixture, held until another bearing
// is bearing_switch_ratio times as probable; checked step by step against an independent
// BearingDensity over weak-signal walks (where the ring stays wide for many steps), several
// seeds so that both branches are exercised whatever the filter's details.
TEST(SearchControllerOpening, HeadsForTheMostProbableBearingWithHysteresis) {
  Scenario s;
  s.transmitter = Vec3(35.0, -30.0, -1.5);
  s.moment = Vec3(0.006, 0.0, 0.004);
  s.receiver = Vec3(0, 0, 1);
  int opening_steps = 0, turns = 0, holds = 0;
  for (std::uint64_t seed = 1; seed <= 24; ++seed) {
    AvalancheSimulator sim(SimulationConfig{}, s, seed);
    SogConfig cfg;
    cfg.initial_components = 600;
    SogFilter f(cfg);
    SearchConfig sc;
    sc.opening_heading = OpeningHeading::kPosteriorBearing;
    sc.approach_mahalanobis = 0.5;  // a long opening
    sc.opening_line_samples = 0;    // the heading rule from the first sample, not the primary line
    SearchController ctl(sc);
    const double kernel = sc.bearing_kernel_deg * kPi / 180.0;
    std::optional<double> held;
    for (int k = 0; k < 40; ++k) {
      const FieldMeasurement z = sim.measure();
      f.process(z);
      const BearingDensity density(f.hypotheses(), kernel);
      const Guidance g = ctl.guide(f, z);
      if (g.mode != GuidanceMode::kOpening) break;
      ++opening_steps;
      if (!held) {
        EXPECT_NEAR(g.heading_rad, wrap_angle(density.peak()), 1e-12);
      } else if (density.at(density.peak()) > sc.bearing_switch_ratio * density.at(*held)) {
        EXPECT_NEAR(g.heading_rad, wrap_angle(density.peak()), 1e-12) << "seed " << seed << " step " << k;
        ++turns;
      } else {
        EXPECT_NEAR(g.heading_rad, wrap_angle(*held), 1e-12) << "seed " << seed << " step " << k;
        ++holds;
      }
      held = g.heading_rad;
      f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
    }
  }
  // Both branches were exercised.
  EXPECT_GE(opening_steps, 60);
  EXPECT_GE(turns, 2);  // 4 turns, 86 holds in 114 opening steps when written
  EXPECT_GE(holds, 20);
}

}  // namespace
}  // namespace sarloc::avalanche

namespace sarloc::avalanche {
namespace {

// A signal lost while the estimate is still a wide ring (search.lost_signal_steps, issue 58):
// after that many unheard epochs the rescuer walks the primary search's line again (the heading
// he had when the signal was first heard), whatever the ring's mean says, and the opening search
// starts over with the next sample. Before it, and with a converged estimate, coast() does what it did.
TEST(SearchControllerLostSignal, AWideSearchLostForLongWalksThePrimaryLineAgain) {
  Scenario s;
  s.transmitter = Vec3(45.0, 20.0, -1.5);
  s.moment = Vec3(0.006, 0.0, 0.004);
  s.receiver = Vec3(0, 0, 1);
  s.receiver_rpy = Vec3(0, 0, 0.3);  // walking the primary line at 0.3 rad
  AvalancheSimulator sim(SimulationConfig{}, s, 3);
  SogConfig cfg;
  cfg.initial_components = 400;
  SogFilter f(cfg);
  SearchConfig sc;
  sc.lost_signal_steps = 15;  // off as shipped (search_controller.hpp)
  SearchController ctl(sc);
  const FieldMeasurement z = sim.measure();
  f.process(z);
  ctl.guide(f, z);
  const double primary = f.moments().mean[idx::kAtt + 2];  // the compass's word for 0.3 rad
  ASSERT_NEAR(primary, 0.3, 0.3);
  ASSERT_GT(radius95_3d(f.moments().covariance.block<3, 3>(idx::kPos, idx::kPos)), f.converged_radius_m());
  for (std::uint32_t k = 1; k < sc.lost_signal_steps; ++k) {
    const Guidance g = ctl.coast(f);
    EXPECT_EQ(ctl.line_resumptions(), 0U) << "epoch " << k;
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  for (int k = 0; k < 5; ++k) {
    const Guidance g = ctl.coast(f);
    EXPECT_EQ(ctl.line_resumptions(), 1U);
    EXPECT_EQ(g.mode, GuidanceMode::kOpening);
    EXPECT_DOUBLE_EQ(g.heading_rad, primary) << "the primary line's heading, held";
    EXPECT_DOUBLE_EQ(g.step_m, sc.step_length_m);
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  const FieldMeasurement heard = sim.measure();
  f.process(heard);
  ctl.guide(f, heard);
  // Heard again: the line is left, and only as many unheard epochs again walk it once more.
  for (std::uint32_t k = 1; k < sc.lost_signal_steps; ++k) {
    const Guidance g = ctl.coast(f);
    EXPECT_EQ(ctl.line_resumptions(), 1U) << "epoch " << k;
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
  }
  ctl.coast(f);
  EXPECT_EQ(ctl.line_resumptions(), 2U);

  SearchConfig off = sc;
  off.lost_signal_steps = 0;
  SearchController never(off);
  never.guide(f, heard);
  for (std::uint32_t k = 0; k < 2 * sc.lost_signal_steps; ++k) never.coast(f);
  EXPECT_EQ(never.line_resumptions(), 0U) << "0 = off";
}

// The re-planned walk is bounded: a signal never heard again keeps the rescuer sweeping the
// line within search.lost_line_half_length_m (plus a step) of where it was last heard, both ways,
// never walking off (a live rescuer walked 299 m "until heard", issue 58).
TEST(SearchControllerLostSignal, TheSweepForASignalNeverHeardAgainStaysNearWhereItWasHeard) {
  Scenario s;
  s.transmitter = Vec3(45.0, 20.0, -1.5);
  s.moment = Vec3(0.006, 0.0, 0.004);
  s.receiver = Vec3(0, 0, 1);
  s.receiver_rpy = Vec3(0, 0, 0.3);
  AvalancheSimulator sim(SimulationConfig{}, s, 5);
  SogConfig cfg;
  cfg.initial_components = 400;
  SogFilter f(cfg);
  SearchConfig sc;
  sc.lost_signal_steps = 15;
  sc.lost_line_half_length_m = 30.0;
  SearchController ctl(sc);
  const FieldMeasurement z = sim.measure();
  f.process(z);
  ctl.guide(f, z);
  const Eigen::Vector2d heard_at = sim.scenario().receiver.head<2>();
  double farthest = 0.0;
  int turns = 0;
  std::optional<double> last_heading;
  for (int k = 0; k < 400; ++k) {
    const Guidance g = ctl.coast(f);
    if (last_heading && std::abs(wrap_angle(g.heading_rad - *last_heading)) > 3.0) ++turns;
    if (ctl.line_resumptions() > 0) last_heading = g.heading_rad;
    f.add_odometry(sim.walk(g.bearing_rad, g.step_m));
    farthest = std::max(farthest, (sim.scenario().receiver.head<2>() - heard_at).norm());
  }
  EXPECT_EQ(ctl.line_resumptions(), 1U);
  EXPECT_GE(turns, 3) << "swept both ways, again and again";
  // The odometry drifts a little over 400 steps: the bound is the filter's word for the place.
  EXPECT_LT(farthest, sc.lost_line_half_length_m + 3.0 * sc.step_length_m);
  EXPECT_GT(farthest, sc.lost_line_half_length_m - sc.step_length_m) << "the sweep reaches its bound";
}

}  // namespace
}  // namespace sarloc::avalanche
