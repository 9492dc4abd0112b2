#include "sarloc/core/avalanche/lookahead_heading.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/avalanche/rotation.hpp"
#include "sarloc/core/common/errors.hpp"
#include "support/config_messages.hpp"

namespace sarloc::avalanche {
namespace {

constexpr double kFloor = 2.1e-9;
const FieldNoiseModel kNoise{0.05, kFloor};

// A hypothesis at `position` (receiver at the origin of G) whose moment explains the field
// `field_at_receiver` exactly: every hypothesis agrees with the reading just taken.
TransmitterHypothesis hypothesis(const Vec3& position, const Vec3& field_at_receiver, double log_weight) {
  return {position, DipoleField::moment(-position, field_at_receiver), std::exp(log_weight)};
}

double angle_between(double a, double b) { return std::abs(wrap_angle(a - b)); }

TEST(LookaheadHeadingTest, WalksTowardsAConcentratedBearing) {
  // An arc of hypotheses 45 m away around 40 degrees: nothing left to learn about the bearing.
  const double bearing = 40.0 * kPi / 180.0;
  const Vec3 field(8e-9, -3e-9, 5e-9);
  std::vector<TransmitterHypothesis> arc;
  for (int k = -5; k <= 5; ++k) {
    const double b = bearing + k * 0.01;
    arc.push_back(hypothesis(Vec3(45.0 * std::cos(b), 45.0 * std::sin(b), -2.5), field,
                             -std::log(11.0)));
  }
  const double heading = lookahead_heading(arc, LookaheadConfig{}, 1.0, kNoise, kFloor);
  EXPECT_LT(angle_between(heading, bearing), 10.0 * kPi / 180.0) << heading;
}

// Two equally likely victims 50 m away at bearings +30 and -30 degrees, both explaining the
// current reading. Heading east between them leaves the least expected distance after the
// imagined walk, and that is what the planner picks without its detour term; but walking
// east approaches both alike and, at this weak signal, hardly tells them apart, so the full
// cost prefers a heading towards one of them, where the field grows quickly if it is the
// victim and slowly if not. (With a strong signal any walk tells them apart and east wins.)
TEST(LookaheadHeadingTest, PrefersTheWalkThatTellsHypothesesApart) {
  const Vec3 field(3.6e-9, 1.2e-9, -2.7e-9);  // |h| about 2 noise floors
  const double b = 30.0 * kPi / 180.0;
  const std::vector<TransmitterHypothesis> pair = {
      hypothesis(Vec3(50.0 * std::cos(b), 50.0 * std::sin(b), -2.0), field, std::log(0.5)),
      hypothesis(Vec3(50.0 * std::cos(b), -50.0 * std::sin(b), -2.0), field, std::log(0.5))};
  LookaheadConfig distance_only;
  distance_only.detour_weight = 0.0;
  const double greedy = lookahead_heading(pair, distance_only, 1.0, kNoise, kFloor);
  EXPECT_LT(angle_between(greedy, 0.0), 10.0 * kPi / 180.0) << greedy;
  const double informed = lookahead_heading(pair, LookaheadConfig{}, 1.0, kNoise, kFloor);
  EXPECT_GT(angle_between(informed, 0.0), 15.0 * kPi / 180.0) << informed;
  EXPECT_LT(angle_between(informed, 0.0), 60.0 * kPi / 180.0) << informed;
}

TEST(LookaheadHeadingTest, ValidationNamesTheKeyAndValue) {
  EXPECT_NO_THROW(LookaheadConfig{}.validate());
  LookaheadConfig c;
  c.headings = 1;
  EXPECT_NE(sarloc::test::validation_error(c).find("search.lookahead_headings = 1"), std::string::npos)
      << sarloc::test::validation_error(c);
  c = LookaheadConfig{};
  c.information_scale = 0.0;
  EXPECT_THROW(c.validate(), ConfigError);
  EXPECT_THROW(lookahead_heading({}, LookaheadConfig{}, 1.0, kNoise, kFloor),
               std::invalid_argument);
}

}  // namespace
}  // namespace sarloc::avalanche
