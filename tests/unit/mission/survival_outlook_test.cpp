// A mission's expected survivors: each FOUND victim's survival at its dig-out minute, counted by
// hand from the curve's points, and a victim never found kept apart as the most it could add.
#include "sarloc/core/mission/survival_outlook.hpp"

#include <gtest/gtest.h>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::mission {
namespace {

VictimOutcome victim(double depth_m, bool found, std::optional<double> found_at_s) {
  VictimOutcome v;
  v.true_position = Vec3(0.0, 30.0, -depth_m);
  v.found = found;
  v.found_at_s = found_at_s;
  return v;
}

TEST(SurvivalOutlook, EachFoundVictimAtItsDigOutMinute) {
  MissionSummary s;
  s.mission_s = 1800.0;  // 30 min
  // 1 m deep, FOUND at 5 min: dug out at 5 + 10 = 15 min (0.92). 2 m deep, FOUND at 10 min,
  // buried 3 min before the search: 3 + 10 + 30 = 43 min, between (35, 0.30) and (90, 0.27).
  s.victims = {victim(1.0, true, 300.0), victim(2.0, true, 600.0), victim(1.0, false, std::nullopt)};
  incident::TriageConfig triage;
  triage.buried_before_start_min = 3.0;
  add_survival_outlook(s, triage);
  ASSERT_TRUE(s.victims[0].survival && s.victims[1].survival);
  EXPECT_DOUBLE_EQ(*s.victims[0].dug_out_min, 18.0);
  EXPECT_NEAR(*s.victims[0].survival, 0.92 + (3.0 / 20.0) * (0.30 - 0.92), 1e-12) << "18 min: past the plateau";
  EXPECT_DOUBLE_EQ(*s.victims[1].dug_out_min, 43.0);
  EXPECT_NEAR(*s.victims[1].survival, 0.30 + (8.0 / 55.0) * (0.27 - 0.30), 1e-12);
  EXPECT_NEAR(*s.expected_survivors, *s.victims[0].survival + *s.victims[1].survival, 1e-12);
  // Not found by the end (30 min): dug out at 3 + 30 + 10 = 43 min at the earliest.
  EXPECT_FALSE(s.victims[2].survival.has_value());
  EXPECT_EQ(s.unfound_count, 1U);
  EXPECT_NEAR(s.unfound_survival_at_most, *s.victims[1].survival, 1e-12) << "the same minute as the 2 m victim";
}

TEST(SurvivalOutlook, FoundSoonerKeepsMoreAlive) {
  auto survivors_when_found_at = [](double found_at_s) {
    MissionSummary s;
    s.mission_s = 3600.0;
    s.victims = {victim(1.5, true, found_at_s)};
    add_survival_outlook(s, incident::TriageConfig{});
    return *s.expected_survivors;
  };
  EXPECT_GT(survivors_when_found_at(240.0), survivors_when_found_at(600.0));
  EXPECT_GT(survivors_when_found_at(600.0), survivors_when_found_at(900.0));
}

TEST(SurvivalOutlook, RefusesAnInvalidCurveOrBurialTime) {
  MissionSummary s;
  s.victims = {victim(1.0, true, 60.0)};
  incident::TriageConfig rising;
  rising.survival_curve = {{0.0, 0.5}, {10.0, 0.6}};
  EXPECT_THROW(add_survival_outlook(s, rising), ConfigError);
  try {
    incident::TriageConfig buried_later;
    buried_later.buried_before_start_min = -1.0;
    add_survival_outlook(s, buried_later);
    FAIL() << "a negative burial time was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("triage.buried_before_start_min"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(s.expected_survivors.has_value()) << "a refused outlook changes nothing";
}

}  // namespace
}  // namespace sarloc::mission
