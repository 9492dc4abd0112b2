// The map-aided particle filter (seed 004 section IV-E) on simulated searches with the real INS:
// a known start tracks within a metre, particles never end on the far side of a wall from
// where they were, floors change only on stairs, bad input is refused, the map-error flag rises
// when a door moves, and the Monte Carlo NEES of its estimate is reported by the evaluation
// (this test bounds it from above: the filter must not claim more than it knows).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/firefighter/cloud_places.hpp"
#include "sarloc/core/firefighter/firefighter_evaluation.hpp"
#include "sarloc/core/firefighter/pattern_matcher.hpp"
#include "test_buildings.hpp"

namespace sarloc::firefighter {
namespace {

FirefighterEvalConfig short_config(std::uint32_t runs) {
  FirefighterEvalConfig c;
  c.runs = runs;
  c.walk.duration_s = 150.0;
  c.threads = 1;
  return c;
}

const VariantSummary& variant(const FirefighterSummary& s, const std::string& name) {
  for (const auto& v : s.variants) {
    if (v.variant.name == name) return v;
  }
  throw std::runtime_error("no variant " + name);
}

TEST(MapParticleFilter, KnownStartTracksWithinAMetreAndIsNotOverconfident) {
  const FloorPlan plan = test::building("house-125");
  std::vector<FilterVariant> known;
  for (const FilterVariant& v : standard_variants()) {
    if (v.known_initial_state) known.push_back(v);
  }
  const FirefighterEvaluation eval(plan, short_config(4), known);
  const FirefighterSummary s = eval.run();
  EXPECT_LT(s.ins_drift_median, 1.0);
  for (const char* name : {"known/no-pseudo", "known/weights"}) {
    const VariantSummary& v = variant(s, name);
    EXPECT_LT(v.overall_rmse_m, 1.0) << name;
    ASSERT_GT(v.nees_members, 0U) << name;
    EXPECT_LT(v.nees_mean, v.nees_upper) << name << ": NEES above its chi-square bound";
  }
}

TEST(MapParticleFilter, ChangesFloorOnlyOnTheStairs) {
  const FloorPlan plan = test::building("office-253");
  const NavigableGrid grid = navigable_grid(plan, PatternGridConfig{});
  MapParticleFilter pf(plan, grid, MapFilterConfig{});
  std::mt19937_64 rng(1);
  // At the foot of the flight, facing up it (+y): 5 m forward while climbing 3 m.
  pf.init_known({10.75, 3.0}, 0, 0.5 * 3.14159265358979, rng);
  for (int k = 0; k < 25; ++k) pf.predict(Eigen::Vector3d(0.22, 0.0, 0.135), rng);
  EXPECT_EQ(pf.estimate().floor, 1U) << "at the top of the stairs";
  // Away from the stairs, a climb without stairs removes every particle: the map disagrees.
  MapParticleFilter flat(plan, grid, MapFilterConfig{});
  flat.init_known({2.5, 2.5}, 0, 0.0, rng);
  for (int k = 0; k < 10; ++k) flat.predict(Eigen::Vector3d(0.0, 0.0, 0.2), rng);
  EXPECT_EQ(flat.estimate().floor, 0U);
  EXPECT_TRUE(flat.estimate().map_error_suspected);
  // Standing there 40 s converged clears the flag; that it was raised stays said.
  for (int k = 0; k < 80; ++k) flat.predict(Eigen::Vector3d::Zero(), rng);
  EXPECT_FALSE(flat.estimate().map_error_suspected);
  EXPECT_TRUE(flat.estimate().map_error_since_start);
  flat.init_known({2.5, 2.5}, 0, 0.0, rng);
  EXPECT_FALSE(flat.estimate().map_error_since_start) << "a new start";
}

TEST(MapParticleFilter, RemovesParticlesThatCrossAWall) {
  const FloorPlan plan = test::building("house-125");
  const NavigableGrid grid = navigable_grid(plan, PatternGridConfig{});
  MapFilterConfig config;
  config.known_position_sigma_m = 0.3;
  MapParticleFilter pf(plan, grid, config);
  std::mt19937_64 rng(2);
  pf.init_known({3.5, 5.0}, 0, -0.5 * 3.14159265358979, rng);  // in the corridor, facing door_a (south)
  for (int k = 0; k < 8; ++k) pf.predict(Eigen::Vector3d(0.25, 0.0, 0.0), rng);
  // Two metres south: through door_a into room A, or still in the corridor; a particle in
  // room B (its door is 4 m east) would have walked through the corridor wall.
  for (const Particle& p : pf.particles()) {
    EXPECT_FALSE(p.position.y() < 4.0 && p.position.x() > 5.0) << p.position.transpose();
  }
  EXPECT_LT(std::abs(pf.estimate().position.x() - 3.5), 0.6);
  EXPECT_LT(pf.estimate().position.y(), 4.0) << "most of the weight went through the door";
}

// KLD-sampling (map_particle_filter.hpp): an unknown start holds every particle while the cloud
// is spread; a converged cloud sheds them down towards the paper's 500; a fixed count stays fixed.
TEST(MapParticleFilter, HoldsEveryParticleWhileSpreadAndShedsThemOnceConverged) {
  const FloorPlan plan = test::building("house-125");
  const NavigableGrid grid = navigable_grid(plan, PatternGridConfig{});
  const MapFilterConfig config;
  MapParticleFilter pf(plan, grid, config);
  std::mt19937_64 rng(4);
  pf.init_unknown(rng);
  const std::size_t spread = pf.particles().size();
  EXPECT_EQ(spread, config.particles_max);
  for (int k = 0; k < 8; ++k) pf.predict(Eigen::Vector3d(0.25, 0.0, 0.0), rng);
  ASSERT_FALSE(pf.estimate().converged);
  EXPECT_EQ(pf.particles().size(), spread) << "shed while still spread over the house";

  pf.init_known({3.5, 5.0}, 0, 0.0, rng);  // in the corridor, walking east along it
  EXPECT_EQ(pf.particles().size(), config.particles);
  for (int k = 0; k < 8; ++k) pf.predict(Eigen::Vector3d(0.25, 0.0, 0.0), rng);
  ASSERT_TRUE(pf.estimate().converged);
  EXPECT_GE(pf.particles().size(), config.particles);
  EXPECT_LE(pf.particles().size(), 3000U) << "a converged cloud needs no more";

  MapFilterConfig fixed;
  fixed.particles_max = fixed.particles;
  MapParticleFilter paper(plan, grid, fixed);
  paper.init_unknown(rng);
  for (int k = 0; k < 8; ++k) paper.predict(Eigen::Vector3d(0.25, 0.0, 0.0), rng);
  EXPECT_EQ(paper.particles().size(), fixed.particles);
}

// From an unknown start on the two-floor office, the adaptive count finds the firefighters and
// its converged claims are honest. An honest 99 % ellipse leaves about 1 % of the truths outside,
// so no more than 2 % may be (here 1.4 %: one claim 2.3 m off with 0.74 m sd for 3 s, standing,
// until walking corrected it; docs/estimation/firefighter.md).
TEST(MapParticleFilter, UnknownStartConvergesOnTheOfficeAndItsClaimsAreHonest) {
  const FloorPlan plan = test::building("office-253");
  FirefighterEvalConfig c = short_config(2);
  const FirefighterEvaluation eval(plan, c, {{"unknown/weights", false, true, PseudoResampling::kNever}});
  const FirefighterSummary s = eval.run();
  const VariantSummary& v = variant(s, "unknown/weights");
  EXPECT_LT(v.final_rmse_m, 1.5);
  EXPECT_LE(v.converged_wrong_fraction, 0.02);
  EXPECT_LT(v.particles_mean, 0.75 * c.filter.particles_max) << "the count never came down";
}

// observation_ends: the update weights a concentrated cloud exactly as from the full comparison
// (pruning off, see the matcher's test), from a comparison of a fraction of the windows; it asks
// for every observation while the q % replacement is due, and for none without
// pseudo-observations.
TEST(MapParticleFilter, WeightsFromTheComparisonNearTheCloudEqualTheFullOnes) {
  const FloorPlan plan = test::building("house-125");
  const NavigableGrid grid = navigable_grid(plan, PatternGridConfig{});
  const auto sequences = extract_node_sequences(plan, PatternGridConfig{});
  PatternMatchConfig no_pruning;
  no_pruning.prune_margin_m = 100.0;
  const PatternMatcher matcher(sequences, PatternGridConfig{}, no_pruning);
  const auto& nodes = sequences.front().nodes;
  std::vector<Vec2> walked;
  for (std::size_t k = 0; k <= 20; ++k) walked.push_back(nodes[(30 + k) % nodes.size()]);
  const Vec2 last = walked.back() - walked[walked.size() - 2];
  const double walk_heading = std::atan2(last.y(), last.x());
  MapFilterConfig config;
  config.known_position_sigma_m = 0.8;
  config.known_heading_sigma_deg = 30.0;
  auto filter_at_the_end = [&](const MapFilterConfig& c) {
    auto pf = std::make_unique<MapParticleFilter>(plan, grid, c);
    std::mt19937_64 rng(11);
    pf->init_known(walked.back(), 0, 0.0, rng);
    return pf;
  };
  auto full = filter_at_the_end(config), near = filter_at_the_end(config);
  const std::optional<EndMask> ends = near->observation_ends(matcher);
  ASSERT_TRUE(ends.has_value());
  EXPECT_LT(matcher.windows_touching(*ends), matcher.window_count() / 2);
  std::mt19937_64 rng_full(5), rng_near(5);
  full->update(matcher.compare(walked), walk_heading, rng_full);
  near->update(matcher.compare(walked, &*ends), walk_heading, rng_near);
  ASSERT_EQ(full->weights().size(), near->weights().size());
  for (std::size_t i = 0; i < full->weights().size(); ++i) {
    ASSERT_EQ(full->weights()[i], near->weights()[i]) << i;
    ASSERT_EQ(full->particles()[i].position, near->particles()[i].position) << i;
  }
  EXPECT_EQ(full->estimate().position, near->estimate().position);

  MapFilterConfig replacing = config;
  replacing.resampling = PseudoResampling::kAlways;
  EXPECT_FALSE(filter_at_the_end(replacing)->observation_ends(matcher).has_value()) << "replacement draws from all";
  MapFilterConfig none = config;
  none.pseudo_observations = false;
  const auto nothing = filter_at_the_end(none)->observation_ends(matcher);
  ASSERT_TRUE(nothing.has_value());
  EXPECT_EQ(matcher.windows_touching(*nothing), 0U);
}

TEST(MapParticleFilter, RefusesNonFiniteOdometry) {
  const FloorPlan plan = test::building("house-125");
  const NavigableGrid grid = navigable_grid(plan, PatternGridConfig{});
  MapParticleFilter pf(plan, grid, MapFilterConfig{});
  std::mt19937_64 rng(3);
  pf.init_unknown(rng);
  EXPECT_THROW(pf.predict(Eigen::Vector3d(NAN, 0, 0), rng), InputError);
  EXPECT_THROW(pf.update({PseudoObservation{}}, INFINITY, rng), InputError);
  pf.predict(Eigen::Vector3d(0.1, 0, 0), rng);  // still usable
}

TEST(MapParticleFilter, RaisesTheMapErrorFlagWhenADoorHasMoved) {
  const FloorPlan plan = test::building("house-125");
  FirefighterEvalConfig c = short_config(1);
  c.walk.duration_s = 300.0;
  const FirefighterEvaluation eval(plan, c);
  const MapErrorExperiment m = eval.map_error_experiment("", 2.0);
  ASSERT_FALSE(m.timeline.empty());
  EXPECT_TRUE(m.raised) << "door " << m.door;
}

// Two observations 1 m apart along x from `at` (a grid node of the plan), with these fits.
std::vector<PseudoObservation> two_observations(const Vec2& at, double near_rmse, double far_rmse) {
  std::vector<PseudoObservation> observations(2);
  observations[0].position = at;
  observations[0].rmse = near_rmse;
  observations[1].position = at + Vec2(1.0, 0.0);
  observations[1].rmse = far_rmse;
  return observations;
}

// Tracking, a comparison weighs with likelihood_sigma_converged; finding the place, and for good
// once a map error was suspected, with likelihood_sigma. Two observations 1 m apart, the far one
// a better fit by 0.2 m: the weight on the near side is multiplied by exactly
// outlier + (1 - outlier) exp(-0.2 / sigma^2) against the far side's.
TEST(MapParticleFilter, AConvergedCloudWeighsTheComparisonsWithItsOwnSigmaUntilAMapError) {
  const FloorPlan plan = test::building("house-125");
  const NavigableGrid grid = navigable_grid(plan, PatternGridConfig{});
  const Vec2 at = grid.nodes_per_floor[0][grid.nodes_per_floor[0].size() / 2];
  const std::vector<PseudoObservation> observations = two_observations(at, 0.3, 0.1);
  MapFilterConfig config;
  config.known_position_sigma_m = 0.6;  // converged (variance 0.72 m2), over both observations
  config.position_noise_m = 0.0;        // the moves below bring every particle back exactly
  config.heading_noise_deg_per_m = 0.0;
  // Share of the weight nearer the better fit, before and after one update; and the flags.
  auto shares = [&](bool map_error) {
    MapParticleFilter pf(plan, grid, config);
    std::mt19937_64 rng(7);
    pf.init_known(at, 0, 0.0, rng);
    if (map_error) {  // through the outer walls and back: every particle dies twice
      pf.predict(Eigen::Vector3d(200.0, 0.0, 0.0), rng);
      pf.predict(Eigen::Vector3d(-200.0, 0.0, 0.0), rng);
    }
    EXPECT_TRUE(pf.estimate().converged);
    EXPECT_EQ(pf.estimate().map_error_since_start, map_error);
    auto far_share = [&] {
      double w = 0.0;
      for (std::size_t i = 0; i < pf.particles().size(); ++i) {
        if (pf.particles()[i].position.x() > at.x() + 0.5) w += pf.weights()[i];
      }
      return w;
    };
    const double before = far_share();
    pf.update(observations, 0.0, rng);
    return std::make_pair(before, far_share());
  };
  auto expected = [&](double before, double sigma) {
    const double outlier = config.pattern_outlier_probability;
    const double r = 1.0 / (outlier + (1.0 - outlier) * std::exp(-0.2 / (sigma * sigma)));
    return before * r / (before * r + 1.0 - before);
  };
  const auto [tracking_before, tracking_after] = shares(false);
  ASSERT_GT(tracking_before, 0.1);
  EXPECT_NEAR(tracking_after, expected(tracking_before, config.likelihood_sigma_converged), 1e-9);
  const auto [error_before, error_after] = shares(true);
  EXPECT_NEAR(error_after, expected(error_before, config.likelihood_sigma), 1e-9);
  EXPECT_GT(error_after - error_before, tracking_after - tracking_before);
}

// A comparison may say nothing of a place (the walk of the last 20 m is none of the plan's
// patterns there): one fit far worse than the best costs a particle the outlier factor, not
// exp(-(E - E_best) / sigma^2) (e^-20 for a fit 5 m worse at sigma 0.5: the true place of a walk
// that swept a room died so on the 1040 m2 floor; docs/estimation/firefighter.md).
TEST(MapParticleFilter, APoorFitCostsAParticleAtMostTheOutlierFactor) {
  const FloorPlan plan = test::building("house-125");
  const NavigableGrid grid = navigable_grid(plan, PatternGridConfig{});
  const Vec2 at = grid.nodes_per_floor[0][grid.nodes_per_floor[0].size() / 2];
  const std::vector<PseudoObservation> observations = two_observations(at, 5.2, 0.2);
  for (const double outlier : {0.0, 0.2}) {
    MapFilterConfig config;
    config.pattern_outlier_probability = outlier;
    config.known_position_sigma_m = 0.6;
    config.weight_floor_factor = 0.0;  // no particle is replaced: the weights alone are compared
    MapParticleFilter pf(plan, grid, config);
    std::mt19937_64 rng(3);
    pf.init_known(at, 0, 0.0, rng);
    auto near_share = [&] {
      double w = 0.0;
      for (std::size_t i = 0; i < pf.particles().size(); ++i) {
        if (pf.particles()[i].position.x() < at.x() + 0.5) w += pf.weights()[i];
      }
      return w;
    };
    const double before = near_share();
    ASSERT_GT(before, 0.1);
    ASSERT_TRUE(pf.estimate().converged);  // so the comparison weighs with likelihood_sigma_converged
    pf.update(observations, 0.0, rng);
    const double sigma = config.likelihood_sigma_converged;
    const double factor = outlier + (1.0 - outlier) * std::exp(-5.0 / (sigma * sigma));
    EXPECT_NEAR(near_share(), before * factor / (before * factor + 1.0 - before), 1e-9) << "outlier " << outlier;
  }
}

// Confirmed = converged for confirm_after_steps in a row, no map error since the start, and the
// weight descending from particles drawn near an entry (map_particle_filter.hpp). The
// bookkeeping: an unknown start marks exactly the particles within entry_radius_m of an entry; a
// known start marks all; a map error since the start withholds the confirmation for good.
double near_entry_count(const MapParticleFilter& pf) {
  return static_cast<double>(
      std::count_if(pf.particles().begin(), pf.particles().end(), [](const Particle& p) { return p.from_entry; }));
}

TEST(MapParticleFilter, ConfirmsOnlyAConvergedCloudThatBeganAtAnEntryAndNeverMetAMapError) {
  const FloorPlan plan = test::building("house-125");
  const NavigableGrid grid = navigable_grid(plan, PatternGridConfig{});
  MapFilterConfig config;
  std::mt19937_64 rng(11);
  MapParticleFilter pf(plan, grid, config);
  pf.init_unknown(rng);
  ASSERT_EQ(plan.entries.size(), 1U);
  double near_entry = 0.0;
  for (std::size_t i = 0; i < pf.particles().size(); ++i) {
    const bool near = (pf.particles()[i].position - plan.entries[0].position).norm() <= config.entry_radius_m;
    EXPECT_EQ(pf.particles()[i].from_entry, near) << i;
    near_entry += near ? pf.weights()[i] : 0.0;
  }
  // A walk that came in: the weight near the entry is the prior, however many particles are there.
  ASSERT_LT(near_entry_count(pf), 0.5 * static_cast<double>(pf.particles().size()));
  EXPECT_NEAR(near_entry, config.entry_prior, 1e-9);
  EXPECT_NEAR(pf.estimate().entry_lineage, near_entry, 1e-12);
  EXPECT_FALSE(pf.estimate().confirmed) << "spread over the house";
  // Met inside (a daemon restarted mid-search): uniform, the weight is the particles' share.
  pf.init_unknown(rng, UnknownStart::kInside);
  EXPECT_NEAR(pf.estimate().entry_lineage, near_entry_count(pf) / static_cast<double>(pf.particles().size()), 1e-9);

  pf.init_known({2.5, 5.0}, 0, 0.0, rng);  // in the corridor, walking east along it
  for (std::uint32_t k = 1; k <= config.confirm_after_steps; ++k) {
    pf.predict(Eigen::Vector3d(0.25, 0.0, 0.0), rng);
    EXPECT_TRUE(pf.estimate().converged);
    EXPECT_EQ(pf.estimate().confirmed, k == config.confirm_after_steps) << "after " << k << " steps converged";
  }
  EXPECT_NEAR(pf.estimate().entry_lineage, 1.0, 1e-9);

  config.position_noise_m = 0.0;  // the moves below bring every particle back exactly
  config.heading_noise_deg_per_m = 0.0;
  MapParticleFilter disturbed(plan, grid, config);
  disturbed.init_known({3.5, 5.0}, 0, 0.0, rng);
  disturbed.predict(Eigen::Vector3d(200.0, 0.0, 0.0), rng);  // through the outer walls and back
  disturbed.predict(Eigen::Vector3d(-200.0, 0.0, 0.0), rng);
  ASSERT_TRUE(disturbed.estimate().map_error_since_start);
  EXPECT_TRUE(disturbed.estimate().converged);
  EXPECT_FALSE(disturbed.estimate().confirmed);
}

// The 1040 m2 floor's alike corridors, seed 3 of 150 s walks with the INS as it was before issue
// 62 (5 s alignment, its whole spell for the gyro bias, no zero angular rate or level floor
// updates, a ZUPT blind to the boot's rotation; with them, seeds 3-8 no longer converged wrongly).
FirefighterEvalConfig warehouse_walk_with_the_old_ins() {
  FirefighterEvalConfig c = short_config(1);
  c.seed = 3;
  c.ins.alignment_s = 5.0;
  c.ins.alignment_bias_s = 5.0;
  c.ins.zupt_rotation_lever_m = 0.0;
  c.ins.zaru_sigma_radps = 0.0;
  c.ins.level_step_m = 0.0;
  return c;
}

// A converged cloud can be wrong; a confirmed one must not be. On the warehouse's alike corridors
// this seed's cloud converges in the wrong one with the filter as seed 004 has it (no outlier
// chance, a uniform start, converged on the spread alone), and it is not confirmed. (House-125 seed 6, its
// half-turn image of room C, did the same until the comparison learnt to pass rooms by.) If the
// filter changes so that this seed no longer converges wrongly, the first assertion says so:
// pick a seed that does. With the shipped filter the same walk converges where the firefighter
// is (the next test).
TEST(MapParticleFilter, ConfirmedClaimsFromAnUnknownStartAreHonestWhereConvergedOnesAreNot) {
  const std::vector<FilterVariant> unknown{{"unknown/weights", false, true, PseudoResampling::kNever}};
  {
    // This walk's cloud converges on the wrong corridor: the confirmation rule is what is tested.
    FirefighterEvalConfig c = warehouse_walk_with_the_old_ins();
    c.filter.pattern_outlier_probability = 0.0;
    c.filter.entry_prior = 0.0;
    c.filter.converged_entry_share = 0.0;
    const VariantSummary& v = variant(FirefighterEvaluation(test::building("warehouse-1040"), c, unknown).run(), "unknown/weights");
    ASSERT_GT(v.converged_wrong_fraction, 0.02) << "this seed no longer shows a wrong convergence";
    EXPECT_LE(v.confirmed_wrong_fraction, 0.01);
  }
  {
    // Right claims are confirmed (0.44 of the converged estimates here; 0.24-0.63 over house-125
    // seeds 1-8 at --runs 10: docs/estimation/firefighter.md).
    FirefighterEvalConfig c = short_config(2);
    c.seed = 6;
    const VariantSummary& v = variant(FirefighterEvaluation(test::building("house-125"), c, unknown).run(), "unknown/weights");
    EXPECT_GT(v.confirmed_share, 0.3);
    EXPECT_LE(v.confirmed_wrong_fraction, 0.01);
  }
}

// Issue 65: the shipped filter on walks where seed 004's converged on a look-alike corridor: the
// old INS's walk above (seed 3) and the present INS's seed 1, whose clouds converged outside
// their own 99 % ellipse 100 % and 82 % of the time with no outlier chance, a uniform start and
// the spread alone for convergence (checked 2026-12-06). An honest ellipse leaves about 1 % out; none here may leave
// more than 2 %.
TEST(MapParticleFilter, OnTheWarehouseAnUnknownStartConvergesOnlyWhereTheFirefighterIs) {
  const std::vector<FilterVariant> unknown{{"unknown/weights", false, true, PseudoResampling::kNever}};
  const FirefighterEvalConfig old_ins = warehouse_walk_with_the_old_ins();
  FirefighterEvalConfig seed1 = short_config(2);
  seed1.walk.duration_s = 300.0;
  for (const FirefighterEvalConfig& c : {old_ins, seed1}) {
    const VariantSummary& v =
        variant(FirefighterEvaluation(test::building("warehouse-1040"), c, unknown).run(), "unknown/weights");
    EXPECT_LE(v.converged_wrong_fraction, 0.02) << "seed " << c.seed;
    EXPECT_LE(v.confirmed_wrong_fraction, 0.01) << "seed " << c.seed;
    // Before it converges the cloud is between look-alike corridors and says so (13 % and 20 %
    // of the estimates here), and the truth is in one of them (in all but 0 % and 0.8 %).
    EXPECT_GT(v.ambiguous_share, 0.02) << "seed " << c.seed;
    EXPECT_LE(v.ambiguous_wrong_fraction, 0.05) << "seed " << c.seed;
  }
}

// The places of a cloud: particles in touching 1 m cells are one place, apart ones another, a
// place on another floor another; heaviest first, weights shared out, weighted means.
TEST(CloudPlaces, TouchingCellsAreOnePlaceApartOnesAnother) {
  std::vector<Particle> particles(5);
  std::vector<double> weights{0.2, 0.2, 0.3, 0.1, 0.2};
  particles[0].position = {0.2, 0.2};
  particles[1].position = {1.6, 0.4};  // the next cell east: the same place
  particles[2].position = {10.5, 10.5};
  particles[3].position = {0.3, 0.3};
  particles[3].floor = 1;              // above the first: another place
  particles[4].position = {3.2, 0.5};  // two cells from the second: another place
  const std::vector<Place> places = cloud_places(particles, weights);
  ASSERT_EQ(places.size(), 4U);
  EXPECT_NEAR(places[0].weight, 0.4, 1e-12);
  EXPECT_LT((places[0].position - Vec2(0.9, 0.3)).norm(), 1e-12);
  EXPECT_NEAR(places[0].covariance(0, 0), 0.49, 1e-12);
  EXPECT_NEAR(places[1].weight, 0.3, 1e-12);
  EXPECT_NEAR(places[2].weight, 0.2, 1e-12);
  EXPECT_EQ(places[2].floor, 0U);
  EXPECT_NEAR(places[3].weight, 0.1, 1e-12);
  EXPECT_EQ(places[3].floor, 1U);
}

}  // namespace
}  // namespace sarloc::firefighter
