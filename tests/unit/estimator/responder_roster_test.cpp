// ResponderRoster: who a daemon keeps state for, and when that state goes.
#include "sarloc/core/estimator/responder_roster.hpp"

#include <gtest/gtest.h>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::estimator {
namespace {

using Admission = ResponderRoster::Admission;
using Clock = ResponderRoster::Clock;
using namespace std::chrono_literals;

TEST(ResponderRoster, RosterModeServesOnlyTheListed) {
  ResponderRoster roster({false, {"r1", "r2"}, 256, 60.0});
  const auto t = Clock::now();
  EXPECT_EQ(roster.admit("r1", t), Admission::kNew);
  EXPECT_EQ(roster.admit("r1", t + 1s), Admission::kServed);
  EXPECT_EQ(roster.admit("intruder-7", t), Admission::kNotListed);
  EXPECT_EQ(roster.admit("", t), Admission::kEmptyId);
  EXPECT_EQ(roster.served(), 1U);
  EXPECT_FALSE(roster.open());
}

TEST(ResponderRoster, AnEmptyRosterServesNobody) {
  ResponderRoster roster({false, {}, 256, 60.0});
  EXPECT_EQ(roster.admit("r1", Clock::now()), Admission::kNotListed);
  EXPECT_STREQ(reason_of(Admission::kNotListed), "unknown_rescuer");
}

TEST(ResponderRoster, ManyUnknownIdsLeaveNothingBehind) {
  ResponderRoster roster({false, {"r1"}, 256, 60.0});
  const auto t = Clock::now();
  for (int k = 0; k < 100000; ++k) ASSERT_TRUE(refused(roster.admit("intruder-" + std::to_string(k), t)));
  EXPECT_EQ(roster.served(), 0U);
  EXPECT_EQ(roster.admit("r1", t), Admission::kNew);
}

TEST(ResponderRoster, OpenModeStopsAtMaxResponders) {
  ResponderRoster roster({true, {}, 3, 60.0});
  const auto t = Clock::now();
  EXPECT_EQ(roster.admit("a", t), Admission::kNew);
  EXPECT_EQ(roster.admit("b", t), Admission::kNew);
  EXPECT_EQ(roster.admit("c", t), Admission::kNew);
  EXPECT_EQ(roster.admit("d", t), Admission::kFull);
  EXPECT_STREQ(reason_of(Admission::kFull), "too_many_rescuers");
  EXPECT_EQ(roster.admit("a", t), Admission::kServed);  // the served keep being served
  EXPECT_EQ(roster.served(), 3U);
}

TEST(ResponderRoster, IdleStateIsEvictedOldestFirstAndItsSlotFrees) {
  ResponderRoster roster({true, {}, 2, 60.0});
  const auto t = Clock::now();
  roster.admit("a", t);
  roster.admit("b", t + 10s);
  EXPECT_EQ(roster.admit("c", t + 20s), Admission::kFull);
  EXPECT_TRUE(roster.evict_idle(t + 59s).empty());
  roster.admit("b", t + 65s);  // heard again: stays
  const auto gone = roster.evict_idle(t + 75s);
  ASSERT_EQ(gone.size(), 1U);
  EXPECT_EQ(gone[0], "a");
  EXPECT_EQ(roster.admit("c", t + 76s), Admission::kNew);
  EXPECT_EQ(roster.admit("a", t + 77s), Admission::kFull);
}

TEST(ResponderRoster, AListedResponderEvictedWhenIdleStartsAfreshWhenHeardAgain) {
  ResponderRoster roster({false, {"r1"}, 256, 30.0});
  const auto t = Clock::now();
  roster.admit("r1", t);
  EXPECT_EQ(roster.evict_idle(t + 31s), std::vector<std::string>{"r1"});
  EXPECT_EQ(roster.served(), 0U);
  EXPECT_EQ(roster.admit("r1", t + 40s), Admission::kNew);
}

TEST(ResponderRoster, AnOlderArrivalDoesNotMakeAResponderLookIdle) {
  ResponderRoster roster({true, {}, 4, 30.0});
  const auto t = Clock::now();
  roster.admit("a", t + 20s);
  roster.admit("a", t);  // another listener thread, stamped earlier
  EXPECT_TRUE(roster.evict_idle(t + 40s).empty());
}

TEST(ResponderRoster, ConfigErrorsNameTheKey) {
  try {
    ResponderRoster({true, {}, 4, 0.0});
    FAIL() << "idle_evict_s = 0 accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("core.idle_evict_s"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ResponderRoster({true, {}, 0, 60.0}), ConfigError);
  EXPECT_THROW(ResponderRoster({false, {"r1", ""}, 4, 60.0}), ConfigError);
}

}  // namespace
}  // namespace sarloc::estimator
