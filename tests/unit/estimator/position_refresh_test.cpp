#include "sarloc/core/estimator/position_refresh.hpp"

#include <gtest/gtest.h>

using namespace std::chrono_literals;
using sarloc::estimator::PositionRefresh;

namespace {

sarloc::responder::ResponderPosition at(const std::string& id, std::int64_t stamp) {
  sarloc::responder::ResponderPosition p;
  p.responder_id = id;
  p.stamp = stamp;
  p.source = sarloc::responder::PositionSource::kMapAided;
  return p;
}

}  // namespace

// A firefighter who falls silent has his last position written again every interval, unchanged;
// one still walking never does (his own positions keep it young).
TEST(PositionRefresh, OnlyASilentResponderIsWrittenAgainEachIntervalWithItsOwnStamp) {
  PositionRefresh refresh(10s);
  const auto t0 = PositionRefresh::Clock::time_point{} + 1000s;
  refresh.written(at("silent", 100), t0);
  for (int s = 0; s <= 25; ++s) {
    refresh.written(at("walking", 200 + s), t0 + std::chrono::seconds(s));
    const auto due = refresh.due(t0 + std::chrono::seconds(s));
    if (s == 10 || s == 20) {
      ASSERT_EQ(due.size(), 1U) << "at " << s << " s";
      EXPECT_EQ(due[0].responder_id, "silent");
      EXPECT_EQ(due[0].stamp, 100) << "a copy keeps the stamp: readers know it is not news";
    } else {
      EXPECT_TRUE(due.empty()) << "at " << s << " s: " << due.size() << " due";
    }
  }
  EXPECT_EQ(refresh.size(), 2U);
}

TEST(PositionRefresh, TheNewestStampIsHeldAndTheOldestWriteComesFirst) {
  PositionRefresh refresh(5s);
  const auto t0 = PositionRefresh::Clock::time_point{} + 1000s;
  refresh.written(at("b", 50), t0 + 1s);
  refresh.written(at("a", 30), t0 + 2s);
  refresh.written(at("a", 20), t0 + 3s);  // overtaken on the way: not the last position
  const auto due = refresh.due(t0 + 10s);
  ASSERT_EQ(due.size(), 2U);
  EXPECT_EQ(due[0].responder_id, "b");
  EXPECT_EQ(due[1].responder_id, "a");
  EXPECT_EQ(due[1].stamp, 30);
  EXPECT_TRUE(refresh.due(t0 + 14s).empty());
  EXPECT_EQ(refresh.due(t0 + 15s).size(), 2U);
}

// A firefighter handed to another sector's daemon: the old daemon stops writing his last
// position again (the new one writes his newer ones); the others' go on.
TEST(PositionRefresh, AForgottenResponderIsNeverWrittenAgain) {
  PositionRefresh refresh(5s);
  const auto t0 = PositionRefresh::Clock::time_point{} + 1000s;
  refresh.written(at("handed", 10), t0);
  refresh.written(at("stays", 20), t0);
  refresh.forget("handed");
  refresh.forget("never-seen");
  const auto due = refresh.due(t0 + 10s);
  ASSERT_EQ(due.size(), 1U);
  EXPECT_EQ(due[0].responder_id, "stays");
  EXPECT_EQ(refresh.size(), 1U);
}

TEST(PositionRefresh, RefusesAnIntervalThatIsNotPositive) { EXPECT_THROW(PositionRefresh(0s), std::invalid_argument); }
