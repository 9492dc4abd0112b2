// The options every node takes (--domain, --epoch-ns, --epoch-wall-ns, --speedup): a bad one is
// refused naming the option and the value before any participant or clock is made.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "sarloc/app/node_options.hpp"
#include "support/config_messages.hpp"

namespace sarloc::app {
namespace {

TEST(NodeOptions, EachOptionIsCheckedNamingItsValue) {
  EXPECT_EQ(sarloc::test::validation_error(NodeOptions{}), "");
  const std::vector<std::pair<void (*)(NodeOptions&), std::string>> cases = {
      {[](NodeOptions& o) { o.domain = 300; }, "--domain = 300: must be in [0, 232] (absent: dds.domain_id)"},
      {[](NodeOptions& o) { o.epoch_ns = -5; }, "--epoch-ns = -5: must be >= 0 (absent: now)"},
      {[](NodeOptions& o) { o.speedup = 250.0; }, "--speedup = 250: must be in [0.1, 100] (as mission.speedup)"},
      {[](NodeOptions& o) { o.speedup = 2.5; }, ""},
  };
  for (const auto& [change, message] : cases) {
    NodeOptions options;
    change(options);
    EXPECT_EQ(sarloc::test::validation_error(options), message);
  }
}

}  // namespace
}  // namespace sarloc::app
