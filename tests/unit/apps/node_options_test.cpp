// The options every node takes (--domain, --epoch-ns, --epoch-wall-ns, --speedup): a bad one is
// refused naming the option and the value before any participant or clock is made.
#include <gtest/gtest.h>

#include "sarloc/app/node_options.hpp"
#include "support/config_messages.hpp"

namespace sarloc::app {
namespace {

TEST(NodeOptions, EachOptionIsCheckedNamingItsValue) {
  EXPECT_EQ(sarloc::test::validation_error(NodeOptions{}), "");
  NodeOptions o;
  o.domain = 300;
  EXPECT_EQ(sarloc::test::validation_error(o), "--domain = 300: must be in [0, 232] (absent: dds.domain_id)");
  o = {};
  o.epoch_ns = -5;
  EXPECT_EQ(sarloc::test::validation_error(o), "--epoch-ns = -5: must be >= 0 (absent: now)");
  o = {};
  o.speedup = 250.0;
  EXPECT_EQ(sarloc::test::validation_error(o), "--speedup = 250: must be in [0.1, 100] (as mission.speedup)");
  o.speedup = 2.5;
  EXPECT_EQ(sarloc::test::validation_error(o), "");
}

}  // namespace
}  // namespace sarloc::app
