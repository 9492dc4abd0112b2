// SogConfig: its defaults are valid and each bad value is named with its key.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sarloc/core/avalanche/odometry_accumulator.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sog_scenarios.hpp"
#include "support/config_messages.hpp"

namespace sarloc::avalanche {
namespace {

using namespace test;  // sog_scenarios.hpp

TEST(SogConfigTest, DefaultsValidAndMessagesNameKeyAndValue) {
  EXPECT_NO_THROW(SogConfig{}.validate());
  SogConfig c;
  c.initial_components = 0;
  EXPECT_EQ(sarloc::test::validation_error(c), "sog.initial_components = 0: must be > 0");
  SogConfig d;
  d.noise_floor_A_per_m = kNaN;
  EXPECT_THROW(d.validate(), ConfigError);
  SogConfig e;
  e.standard.field_max_A_per_m = 1e-9;  // below field_min
  EXPECT_THROW(e.validate(), ConfigError);
  EXPECT_THROW(SogFilter{d}, ConfigError);
}

}  // namespace
}  // namespace sarloc::avalanche
