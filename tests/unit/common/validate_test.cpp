// The config checks' one message form, "key = value: rule", with numbers as a file writes them.
#include "sarloc/core/common/validate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sarloc/core/common/errors.hpp"

namespace sarloc {
namespace {

template <typename Check>
std::string message_of(Check check) {
  try {
    check();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST(ConfigValue, PrintsNumbersAsAFileWritesThem) {
  EXPECT_EQ(config_value(0.01), "0.01");
  EXPECT_EQ(config_value(-1.0), "-1");
  EXPECT_EQ(config_value(0.0), "0");
  EXPECT_EQ(config_value(2.1e-9), "2.1e-09");
  EXPECT_EQ(config_value(60.0), "60");
  EXPECT_EQ(config_value(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(config_value(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(std::stod(config_value(0.1 + 0.2)), 0.1 + 0.2) << "reads back as the same double";
}

TEST(Require, NamesTheKeyTheValueAndTheRule) {
  EXPECT_EQ(message_of([] { require(true, "command.cycle_s", 0.25, "must be in (0, 60]"); }), "(nothing thrown)");
  EXPECT_EQ(message_of([] { require(false, "command.cycle_s", -1.0, "must be in (0, 60]"); }),
            "command.cycle_s = -1: must be in (0, 60]");
  EXPECT_EQ(message_of([] { require(false, "core.workers", 0, "must be in [1, 64]"); }), "core.workers = 0: must be in [1, 64]");
  EXPECT_EQ(message_of([] { require(false, "core.node_id", "", "must be 1-64 characters"); }),
            "core.node_id = '': must be 1-64 characters");
  EXPECT_EQ(message_of([] { require(false, "dds.require_security", true, "needs a secure profile"); }),
            "dds.require_security = true: needs a secure profile");
  EXPECT_EQ(message_of([] { check_range("sog", "noise_relative", 1.5, 0.0, 1.0); }),
            "sog.noise_relative = 1.5: must be within [0, 1]");
  EXPECT_EQ(message_of([] { check_range("sog", "noise_relative", std::nan(""), 0.0, 1.0); }),
            "sog.noise_relative = nan: must be within [0, 1]");
}

}  // namespace
}  // namespace sarloc
