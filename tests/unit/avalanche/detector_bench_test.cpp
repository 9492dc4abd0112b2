// The detector bench: its control is honest (a lone pulse's amplitude error is its stated noise),
// its counts are consistent, and a bad setup names the key.
#include "sarloc/core/avalanche/detector_bench.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::avalanche {
namespace {

DetectorBenchSetup bench(DetectorScenario scenario, std::uint32_t draws) {
  DetectorBenchSetup setup;
  setup.scenario = scenario;
  setup.draws = draws;
  setup.seed = 7;
  return setup;
}

TEST(DetectorBench, ALonePulseIsMeasuredWithinItsStatedNoise) {
  const DetectorBenchResult r = run_detector_bench(bench(DetectorScenario::kSingle, 80));
  EXPECT_EQ(r.transmitters, 80U);
  ASSERT_GE(r.error_sigma.size(), 75U) << "a lone pulse 20-70 dB above the noise is found and let through";
  const double median = r.error_sigma[r.error_sigma.size() / 2];
  EXPECT_GT(median, 0.6);  // RMS of six unit normals: median about 0.9
  EXPECT_LT(median, 1.3);
  EXPECT_LT(r.error_sigma.back(), 4.0);
  EXPECT_EQ(r.beyond_10_sigma, 0U);
  EXPECT_LE(r.spurious, 2U);
  EXPECT_GT(r.edges_exact_share, 0.7);
}

TEST(DetectorBench, CountsAgreeAndErrorsAreSorted) {
  for (DetectorScenario s : {DetectorScenario::kNestedPair, DetectorScenario::kTogether}) {
    const DetectorBenchResult r = run_detector_bench(bench(s, 20));
    EXPECT_EQ(r.draws, 20U);
    EXPECT_EQ(r.transmitters, s == DetectorScenario::kNestedPair ? 40U : 80U);
    EXPECT_LE(r.let_through, r.pulses);
    EXPECT_LE(r.spurious, r.pulses);
    EXPECT_LE(r.let_through_spurious, r.spurious);
    EXPECT_EQ(r.error_sigma.size() + r.let_through_spurious, r.let_through);
    EXPECT_EQ(r.error_relative.size(), r.error_sigma.size());
    EXPECT_TRUE(std::is_sorted(r.error_sigma.begin(), r.error_sigma.end()));
    EXPECT_LE(r.beyond_50_sigma, r.beyond_10_sigma);
    EXPECT_GT(r.pulses, 0U) << to_string(s);
  }
}

TEST(DetectorBench, SetupErrorsNameTheKey) {
  DetectorBenchSetup setup = bench(DetectorScenario::kSingle, 0);
  try {
    run_detector_bench(setup);
    FAIL() << "0 draws accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("detector_bench.draws = 0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sarloc::avalanche
