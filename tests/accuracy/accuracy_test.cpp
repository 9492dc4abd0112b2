// Accuracy gates (ctest -L accuracy, run by .ci/run): the configuration the product ships,
// fixed seeds, thresholds that a regression cannot slip under. They assert what the estimators
// achieve, never how fast: speed lives in the benchmarks. docs/benchmarks.md ("Accuracy gates")
// gives each threshold's margin over the spread measured across seeds 1-20, and how it was chosen.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "eval_config.hpp"
#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/core/avalanche/evaluation.hpp"
#include "sarloc/core/avalanche/multi_burial.hpp"
#include "sarloc/core/firefighter/firefighter_evaluation.hpp"
#include "support/dds_test_domains.hpp"

namespace sarloc::test {
namespace {

namespace fs = std::filesystem;
namespace av = avalanche;

const fs::path kSource = SARLOC_SOURCE_DIR;

/// The product's configuration as sarloc-eval runs it: config/eval/avalanche.yaml (trials,
/// seed, budget; every estimator parameter the code's default).
av::EvaluationSetup product_setup(std::uint64_t seed, std::uint32_t trials) {
  av::EvaluationSetup setup;
  eval::load_avalanche_config((kSource / "config/eval/avalanche.yaml").string(), setup);
  setup.evaluation.seed = seed;
  setup.evaluation.trials = trials;
  return setup;
}

std::string lost_trials(const av::EvaluationSummary& s) {
  std::string out;
  for (const auto& t : s.per_trial)
    if (!t.found || t.false_found) out += " " + std::to_string(t.index) + (t.found ? "(false FOUND)" : "(not found)");
  return out;
}

// Realistic receiver, single burial, 2 x 100 trials (seeds 1 and 2). NEES: the mean over the 200
// trials must lie inside what one seed's 100 trials may show, [chi2_300(0.025), chi2_300(0.975)] /
// 100 = [2.54, 3.50]. Per seed, a 95 % bound leaves one consistent seed in 20 outside: the
// shipped filter's seeds 1-20 spread 2.73-3.53 (pooled 3.09; opening with 1700 Gaussians before
// 2026-12-06: 2.69-3.57, pooled 3.15). Pooled, seeds 1-2 give 3.12 (3.36 with 1700); a filter
// 20 % over-confident (the quasi-static field model of before 2026-12-05 with a device free of
// calibration error: 3.40 and 3.84) fails.
TEST(Accuracy, RealisticSingleBurialFindsEveryVictimAccurately) {
  std::uint32_t not_found = 0, false_found = 0;
  double nees_sum = 0.0, nees_lower = 0.0, nees_upper = 0.0;
  std::uint32_t nees_trials = 0;
  for (std::uint64_t seed : {1U, 2U}) {
    const av::EvaluationSummary s = av::run_evaluation(product_setup(seed, 100));
    ASSERT_EQ(s.trials, 100U);
    not_found += s.not_found;
    false_found += s.false_found;
    EXPECT_LE(s.error_m.median, 0.15) << "seed " << seed;
    EXPECT_LE(s.steps.mean, 55.0) << "seed " << seed;
    EXPECT_LE(s.error_m.max, 0.66) << "seed " << seed << ": seed 000's worst SOG error";
    nees_sum += s.nees_mean * s.nees_trials;
    nees_trials += s.nees_trials;
    nees_lower = s.nees_lower;
    nees_upper = s.nees_upper;
    std::printf("realistic seed %llu: not found %u, false FOUND %u, error median %.3f max %.2f m, steps mean %.2f, NEES %.3f;%s\n",
                static_cast<unsigned long long>(seed), s.not_found, s.false_found, s.error_m.median, s.error_m.max,
                s.steps.mean, s.nees_mean, lost_trials(s).c_str());
  }
  EXPECT_LE(not_found, 1U) << "of 200 trials";
  EXPECT_EQ(false_found, 0U) << "a FOUND farther from its victim than its own 95 % radius + 0.5 m";
  ASSERT_GT(nees_trials, 0U);
  const double pooled = nees_sum / nees_trials;
  EXPECT_TRUE(pooled >= nees_lower && pooled <= nees_upper)
      << "NEES over 200 trials " << pooled << " outside [" << nees_lower << ", " << nees_upper << "]";
  std::printf("realistic seeds 1-2: NEES over 200 trials %.3f\n", pooled);
}

// Seed 000's Table I setting (ideal receiver, config/eval/table1.yaml), seeds 1-4 x 100 trials:
// one seed's mean steps spreads 59.0-62.6 over seeds 1-20, so the paper's 62 is held by the mean
// of four (61.3 measured), the rest by every seed.
TEST(Accuracy, IdealReceiverMeetsTableI) {
  double steps = 0.0;
  for (std::uint64_t seed : {1U, 2U, 3U, 4U}) {
    av::EvaluationSetup setup;
    eval::load_avalanche_config((kSource / "config/eval/table1.yaml").string(), setup);
    setup.evaluation.seed = seed;
    setup.evaluation.trials = 100;
    ASSERT_EQ(setup.simulation.receiver.kind, av::ReceiverKind::kIdeal);
    const av::EvaluationSummary s = av::run_evaluation(setup);
    EXPECT_EQ(s.not_found, 0U) << "seed " << seed << ":" << lost_trials(s);
    EXPECT_EQ(s.false_found, 0U) << "seed " << seed << ":" << lost_trials(s);
    EXPECT_LE(s.error_m.max, 0.66) << "seed " << seed;
    EXPECT_TRUE(s.nees_mean >= s.nees_lower && s.nees_mean <= s.nees_upper)
        << "seed " << seed << ": NEES " << s.nees_mean << " outside [" << s.nees_lower << ", " << s.nees_upper << "]";
    steps += s.steps.mean / 4.0;
    std::printf("ideal seed %llu: not found %u, error max %.2f m, steps mean %.2f, NEES %.3f\n",
                static_cast<unsigned long long>(seed), s.not_found, s.error_m.max, s.steps.mean, s.nees_mean);
  }
  EXPECT_LE(steps, 62.0) << "mean steps over seeds 1-4";
}

// Four victims within 5 m of one another, one rescuer, 20 trials: every victim, no ghost, none
// twice. Seed 2: its first 20 trials all find all four (a one-trial margin on 95 %); seed 1's hold
// trial 6, a pair on one carrier in lockstep for 20 minutes that no device separates, which would
// leave the gate no margin at all (docs/benchmarks.md, "Accuracy gates").
TEST(Accuracy, FourVictimsWithinFiveMetresWithoutAGhost) {
  const av::EvaluationSetup base = product_setup(2, 100);
  av::MultiBurialSetup setup = eval::multi_burial_setup(base, 4, 5.0, 20);
  const av::MultiBurialSummary s = av::run_multi_burial(setup);
  ASSERT_EQ(s.trials, 20U);
  EXPECT_GE(s.all_found * 100, 95U * s.trials) << s.all_found << " of " << s.trials << " trials found all four";
  EXPECT_EQ(s.ghosts, 0U) << "a victim confirmed where none is buried";
  EXPECT_EQ(s.duplicates, 0U) << "a victim reported twice";
  std::printf("4 within 5 m, seed 2: all found in %u of %u, ghosts %u, twice %u\n", s.all_found, s.trials, s.ghosts,
              s.duplicates);
}

// Firefighters on house-125 from a known start, 3 searches: RMSE within 1 m at every checkpoint.
TEST(Accuracy, FirefighterFromAKnownStartStaysWithinOneMetre) {
  firefighter::FirefighterEvalConfig config;
  eval::load_firefighter_config((kSource / "config/eval/firefighter.yaml").string(), config);
  config.runs = 3;
  config.seed = 1;
  const firefighter::FloorPlan plan = app::load_floor_plan((kSource / "config/buildings/house-125.yaml").string());
  const auto& f = config.filter;
  const firefighter::FilterVariant known{firefighter::variant_name(true, f.pseudo_observations, f.resampling), true,
                                         f.pseudo_observations, f.resampling};
  const firefighter::FirefighterSummary s = firefighter::FirefighterEvaluation(plan, config, {known}).run();
  ASSERT_EQ(s.variants.size(), 1U);
  const auto& v = s.variants.front();
  ASSERT_FALSE(v.rmse_at_s.empty());
  std::string curve;
  for (std::size_t k = 0; k < v.rmse_at_s.size(); ++k) {
    curve += " " + std::to_string(v.rmse_at_s[k]).substr(0, 4);
    EXPECT_LE(v.rmse_at_s[k], 1.0) << "at " << (k + 1) * config.rmse_every_s << " s";
  }
  std::printf("firefighter house-125 known start, 3 runs: RMSE every %.0f s:%s\n", config.rmse_every_s, curve.c_str());
}

#ifdef SARLOC_WITH_MISSION
// The default mission (scripts/demo): every process over DDS, every victim found once.
TEST(Accuracy, TheDefaultMissionFindsEveryVictimOnce) {
  const fs::path dir = fs::temp_directory_path() / "sarloc-accuracy-default-mission";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string command = std::string(SARLOC_BIN_DIR) + "/sarloc-mission " + (kSource / "config/missions/default.yaml").string() +
                              " --domain " + std::to_string(kDomainAccuracyDefaultMission) + " --run-dir " + dir.string() +
                              " --json " + (dir / "summary.json").string() + " --no-record --log-level warn > " +
                              (dir / "mission.out").string() + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(dir / "summary.json");
  ASSERT_TRUE(in) << "no summary; see " << dir;
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "see " << dir;
  EXPECT_TRUE(summary["all_found"].get<bool>());
  EXPECT_EQ(summary["confirmed_fused_victim_count"], summary["true_victim_count"]) << summary["fused_victims"].dump();
  for (const auto& f : summary["fused_victims"]) {
    if (f["confirmed"].get<bool>()) {
      EXPECT_TRUE(f["matches_a_buried_victim"].get<bool>()) << "confirmed ghost: " << f.dump();
    }
  }
  for (const auto& v : summary["victims"]) {
    ASSERT_FALSE(v["relative_error_m"].is_null()) << v.dump();
    EXPECT_LE(v["relative_error_m"].get<double>(), 0.5) << v.dump();
    EXPECT_LE(v["error_m"].get<double>(), 1.0) << v.dump();
  }
}
#endif

}  // namespace
}  // namespace sarloc::test
