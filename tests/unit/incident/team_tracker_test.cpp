#include "sarloc/core/incident/team_tracker.hpp"

#include <gtest/gtest.h>

#include "sarloc/core/common/errors.hpp"
#include "support/config_messages.hpp"

namespace sarloc::incident {
namespace {

constexpr TimestampNs kSec = 1'000'000'000;

ResponderPosition pos(const std::string& id, const std::string& team, TimestampNs stamp, double x = 0.0) {
  ResponderPosition p;
  p.responder_id = id;
  p.team_id = team;
  p.stamp = stamp;
  p.position.position = Vec3(x, 0.0, 0.0);
  return p;
}

const MemberStatus& member(const std::vector<TeamStatus>& teams, const std::string& id) {
  for (const TeamStatus& t : teams)
    for (const MemberStatus& m : t.members)
      if (m.responder_id == id) return m;
  throw std::runtime_error("no member " + id);
}

TEST(TeamTracker, ConfigValidation) {
  EXPECT_NO_THROW(TeamTrackerConfig{}.validate());
  TeamTrackerConfig c;
  c.stale_after_s = 0.0;
  EXPECT_EQ(sarloc::test::validation_error(c), "team_tracker.stale_after_s = 0: must be > 0");
  c = {};
  c.lost_after_s = 5.0;
  EXPECT_EQ(sarloc::test::validation_error(c), "team_tracker.lost_after_s = 5: must be > stale_after_s");
  EXPECT_THROW(TeamTracker{c}, ConfigError);
}

TEST(TeamTracker, GroupsByTeamSorted) {
  TeamTracker t;
  t.on_position(pos("r2", "alpha", 0), 0);
  t.on_position(pos("r1", "alpha", 0), 0);
  t.on_position(pos("r3", "bravo", 0), 0);
  const auto teams = t.evaluate(kSec);
  ASSERT_EQ(teams.size(), 2u);
  EXPECT_EQ(teams[0].team_id, "alpha");
  ASSERT_EQ(teams[0].members.size(), 2u);
  EXPECT_EQ(teams[0].members[0].responder_id, "r1");
  EXPECT_EQ(teams[0].members[1].responder_id, "r2");
  EXPECT_EQ(teams[1].team_id, "bravo");
  EXPECT_EQ(teams[0].stamp, kSec);
  EXPECT_EQ(t.responders_total(), 3u);
  // team change moves the responder
  t.on_position(pos("r2", "bravo", kSec), kSec);
  EXPECT_EQ(t.evaluate(kSec)[0].members.size(), 1u);
  EXPECT_EQ(t.evaluate(kSec)[1].members.size(), 2u);
}

// Found through sarloc-report on a recorded mission: the daemon's map-aided fixes (no team)
// had moved firefighters into a team "" in the picture.
TEST(TeamTracker, APositionWithoutATeamKeepsTheMemberInItsTeam) {
  TeamTracker t;
  t.on_position(pos("ff1", "alpha", 0), 0);
  t.on_position(pos("ff1", "", kSec), kSec);
  auto teams = t.evaluate(kSec);
  ASSERT_EQ(teams.size(), 1u);
  EXPECT_EQ(teams[0].team_id, "alpha");
  // Heard first without a team: in team "" until its device names one.
  t.on_position(pos("ff2", "", kSec), kSec);
  t.on_position(pos("ff2", "alpha", 2 * kSec), 2 * kSec);
  teams = t.evaluate(2 * kSec);
  ASSERT_EQ(teams.size(), 1u);
  EXPECT_EQ(teams[0].members.size(), 2u);
}

TEST(TeamTracker, AliveStaleLostByTime) {
  TeamTracker t;  // stale after 5 s, lost after 15 s
  t.on_position(pos("r1", "a", 0, 3.0), 0);
  auto m = member(t.evaluate(5 * kSec), "r1");
  EXPECT_EQ(m.link, LinkState::kAlive);
  EXPECT_EQ(m.accountability, AccountabilityState::kAccounted);
  EXPECT_EQ(m.last_seen, 0);
  EXPECT_TRUE(m.has_position);
  EXPECT_DOUBLE_EQ(m.last_position.position.x(), 3.0);
  m = member(t.evaluate(6 * kSec), "r1");
  EXPECT_EQ(m.link, LinkState::kStale);
  EXPECT_EQ(m.accountability, AccountabilityState::kPending);
  m = member(t.evaluate(16 * kSec), "r1");
  EXPECT_EQ(m.link, LinkState::kLost);
  EXPECT_EQ(m.accountability, AccountabilityState::kMissing);
  EXPECT_EQ(t.link_lost_count(16 * kSec), 1u);
  EXPECT_EQ(t.link_lost_count(), 0u);  // latest now seen by the tracker is 0
  // seen again: alive
  t.on_position(pos("r1", "a", 17 * kSec, 4.0), 17 * kSec);
  m = member(t.evaluate(17 * kSec), "r1");
  EXPECT_EQ(m.link, LinkState::kAlive);
  EXPECT_EQ(m.last_seen, 17 * kSec);
  EXPECT_DOUBLE_EQ(m.last_position.position.x(), 4.0);
  EXPECT_EQ(t.link_lost_count(), 0u);
}

TEST(TeamTracker, LivelinessLostIsImmediateAndRecovers) {
  TeamTracker t;
  t.on_position(pos("r1", "a", 0), 0);
  t.on_position(pos("r2", "a", 0), 0);
  t.on_link("r1", false, kSec);
  EXPECT_EQ(member(t.evaluate(kSec), "r1").link, LinkState::kLost);
  EXPECT_EQ(member(t.evaluate(kSec), "r2").link, LinkState::kAlive);
  EXPECT_EQ(t.link_lost_count(), 1u);
  t.on_link("r1", true, 2 * kSec);
  EXPECT_EQ(member(t.evaluate(2 * kSec), "r1").link, LinkState::kAlive);
  EXPECT_EQ(member(t.evaluate(2 * kSec), "r1").last_seen, 2 * kSec);
  t.on_link("r1", false, 3 * kSec);
  t.on_position(pos("r1", "a", 4 * kSec), 4 * kSec);  // a position also brings it back
  EXPECT_EQ(member(t.evaluate(4 * kSec), "r1").link, LinkState::kAlive);
}

TEST(TeamTracker, ASignedOffResponderIsAccountedForAndItsWritersDepartureRaisesNothing) {
  TeamTracker t;
  t.on_position(pos("r1", "alpha", 1 * kSec), 0);
  t.on_position(pos("r2", "alpha", 1 * kSec), 0);
  t.on_signed_off("r1", 2 * kSec);
  t.on_link("r1", false, 2 * kSec);  // its writer leaves right after
  t.on_link("r2", false, 2 * kSec);  // killed: no sign-off
  // Long after, a signed-off responder is still accounted for; silence does not make it lost.
  const auto teams = t.evaluate(100 * kSec);
  EXPECT_EQ(member(teams, "r1").link, LinkState::kSignedOff);
  EXPECT_EQ(member(teams, "r1").accountability, AccountabilityState::kAccounted);
  EXPECT_EQ(member(teams, "r2").link, LinkState::kLost);
  EXPECT_EQ(member(teams, "r2").accountability, AccountabilityState::kMissing);
  EXPECT_EQ(t.link_lost_count(100 * kSec), 1u);

  // A late copy of an older position (the second reader's) leaves the sign-off standing.
  t.on_position(pos("r1", "alpha", 1 * kSec), 101 * kSec);
  EXPECT_EQ(member(t.evaluate(101 * kSec), "r1").link, LinkState::kSignedOff);
  // The device starts again: a newer position, and its next departure is a loss again.
  t.on_position(pos("r1", "alpha", 200 * kSec), 200 * kSec);
  EXPECT_EQ(member(t.evaluate(200 * kSec), "r1").link, LinkState::kAlive);
  t.on_link("r1", false, 201 * kSec);
  EXPECT_EQ(member(t.evaluate(201 * kSec), "r1").link, LinkState::kLost);
  EXPECT_THROW(t.on_signed_off("", 0), InputError);
}

TEST(TeamTracker, AStandbyAdoptsASignOff) {
  TeamTracker active;
  active.on_position(pos("r1", "alpha", 1 * kSec), 0);
  active.on_signed_off("r1", 2 * kSec);
  TeamTracker standby;
  standby.adopt(active.evaluate(3 * kSec));
  EXPECT_EQ(member(standby.evaluate(50 * kSec), "r1").link, LinkState::kSignedOff);
}

TEST(TeamTracker, OlderPositionDoesNotReplaceButCountsAsHeard) {
  TeamTracker t;
  t.on_position(pos("r1", "a", 10 * kSec, 1.0), 10 * kSec);
  t.on_position(pos("r1", "a", 5 * kSec, 9.0), 20 * kSec);
  const auto m = member(t.evaluate(20 * kSec), "r1");
  EXPECT_DOUBLE_EQ(m.last_position.position.x(), 1.0);
  EXPECT_EQ(m.position_stamp, 10 * kSec);
  EXPECT_EQ(m.last_seen, 20 * kSec);
  EXPECT_EQ(m.link, LinkState::kAlive);
}

TEST(TeamTracker, LinkBeforePositionIsUnassigned) {
  TeamTracker t;
  t.on_link("r9", true, 0);
  auto teams = t.evaluate(0);
  ASSERT_EQ(teams.size(), 1u);
  EXPECT_EQ(teams[0].team_id, "");
  EXPECT_FALSE(teams[0].members[0].has_position);
  t.on_position(pos("r9", "c", 0), kSec);
  teams = t.evaluate(kSec);
  ASSERT_EQ(teams.size(), 1u);
  EXPECT_EQ(teams[0].team_id, "c");
  EXPECT_THROW(t.on_link("", true, 0), InputError);
  EXPECT_THROW(t.on_position(pos("", "c", 0), 0), InputError);
}

// A restarted incident command never heard a responder whose device died before it started:
// the active one's published TeamStatus fills that in; what it heard itself stays.
TEST(TeamTracker, AdoptFillsInWhatThisTrackerNeverHeard) {
  TeamTracker active;
  active.on_position(pos("dead", "north", 2 * kSec, 4.0), 2 * kSec);
  active.on_link("dead", false, 5 * kSec);
  active.on_position(pos("alive", "south", 9 * kSec, 7.0), 9 * kSec);
  const auto published = active.evaluate(10 * kSec);

  TeamTracker restarted;
  restarted.on_position(pos("alive", "south", 11 * kSec, 8.0), 11 * kSec);
  restarted.adopt(published);
  const auto teams = restarted.evaluate(12 * kSec);
  const auto dead = member(teams, "dead");
  EXPECT_EQ(dead.link, LinkState::kLost);
  EXPECT_EQ(dead.accountability, AccountabilityState::kMissing);
  EXPECT_TRUE(dead.has_position);
  EXPECT_DOUBLE_EQ(dead.last_position.position.x(), 4.0);
  EXPECT_EQ(dead.position_stamp, 2 * kSec);
  EXPECT_EQ(dead.last_seen, 2 * kSec);
  EXPECT_EQ(teams[0].team_id, "north");
  const auto alive = member(teams, "alive");
  EXPECT_DOUBLE_EQ(alive.last_position.position.x(), 8.0) << "its own, newer position stays";
  EXPECT_EQ(alive.link, LinkState::kAlive);
  EXPECT_EQ(restarted.responders_total(), 2u);

  // Heard again: alive, whatever the picture said.
  restarted.on_position(pos("dead", "north", 13 * kSec, 4.5), 13 * kSec);
  EXPECT_EQ(member(restarted.evaluate(13 * kSec), "dead").link, LinkState::kAlive);

  TeamStatus bad;
  bad.members.push_back(MemberStatus{});
  EXPECT_THROW(restarted.adopt({bad}), InputError);
}

TEST(TeamTracker, MapAidedPositionsOutrankTheDevicesDeadReckoningWhileTheyKeepComing) {
  TeamTracker tracker;
  auto map_aided = pos("ff1", "alpha", 10 * kSec, 5.0);
  map_aided.source = responder::PositionSource::kMapAided;
  map_aided.floor = 1;
  map_aided.confirmed = true;
  tracker.on_position(map_aided, 10 * kSec);
  auto reckoned = pos("ff1", "alpha", 11 * kSec, 6.0);
  reckoned.source = responder::PositionSource::kDeadReckoning;
  tracker.on_position(reckoned, 11 * kSec);
  auto m = member(tracker.evaluate(11 * kSec), "ff1");
  EXPECT_DOUBLE_EQ(m.last_position.position.x(), 5.0) << "the daemon's fix 1 s old stays";
  EXPECT_EQ(m.floor, 1);
  EXPECT_EQ(m.source, responder::PositionSource::kMapAided);
  EXPECT_TRUE(m.confirmed);
  EXPECT_EQ(m.last_seen, 11 * kSec) << "the device was heard all the same";
  reckoned.stamp = 14 * kSec;  // the daemon silent for 4 s: the device's own is the newest known
  reckoned.position.position.x() = 7.0;
  tracker.on_position(reckoned, 14 * kSec);
  m = member(tracker.evaluate(14 * kSec), "ff1");
  EXPECT_DOUBLE_EQ(m.last_position.position.x(), 7.0);
  EXPECT_EQ(m.source, responder::PositionSource::kDeadReckoning);
  EXPECT_FALSE(m.confirmed);
}

// The core daemon writes a silent firefighter's last map-aided position again every 10 s
// (estimator::PositionRefresh): the copies keep the position known and must not keep him alive.
TEST(TeamTracker, CopiesOfTheDaemonsLastPositionDoNotKeepASilentFirefighterAlive) {
  TeamTracker tracker;  // stale after 5 s, lost after 15 s
  auto last = pos("ff1", "", 10 * kSec, 5.0);
  last.source = responder::PositionSource::kMapAided;
  tracker.on_position(last, 10 * kSec);
  for (TimestampNs now = 20 * kSec; now <= 40 * kSec; now += 10 * kSec) tracker.on_position(last, now);
  auto m = member(tracker.evaluate(40 * kSec), "ff1");
  EXPECT_EQ(m.link, LinkState::kLost) << "heard last at 10 s";
  EXPECT_EQ(m.last_seen, 10 * kSec);
  EXPECT_DOUBLE_EQ(m.last_position.position.x(), 5.0);
  // Another's device lost at once (its writer's liveliness): a copy after it does not bring him back.
  auto ff2 = pos("ff2", "alpha", 40 * kSec, 2.0);
  ff2.source = responder::PositionSource::kMapAided;
  tracker.on_position(ff2, 40 * kSec);
  tracker.on_link("ff2", false, 41 * kSec);
  tracker.on_position(ff2, 43 * kSec);
  EXPECT_EQ(member(tracker.evaluate(43 * kSec), "ff2").link, LinkState::kLost);
  // A newer map-aided position is news: his odometry reached the daemon again.
  last.stamp = 50 * kSec;
  last.position.position.x() = 6.0;
  tracker.on_position(last, 50 * kSec);
  m = member(tracker.evaluate(50 * kSec), "ff1");
  EXPECT_EQ(m.link, LinkState::kAlive);
  EXPECT_DOUBLE_EQ(m.last_position.position.x(), 6.0);
}

// A firefighter's device signs off when his search ends; the daemon's answers to its last
// odometry steps can reach incident command after that, with newer stamps. They are not the
// device coming back: he stays signed off, and his writer's departure raises nothing.
TEST(TeamTracker, TheDaemonsAnswersToTheLastStepsDoNotUndoAFirefightersSignOff) {
  TeamTracker tracker;
  auto own = pos("ff3", "bravo", 10 * kSec, 1.0);
  own.source = responder::PositionSource::kDeadReckoning;
  tracker.on_position(own, 10 * kSec);
  tracker.on_signed_off("ff3", 11 * kSec);
  auto answer = pos("ff3", "", 10'500'000'000, 1.2);
  answer.source = responder::PositionSource::kMapAided;
  tracker.on_position(answer, 12 * kSec);
  tracker.on_link("ff3", false, 13 * kSec);
  auto m = member(tracker.evaluate(40 * kSec), "ff3");
  EXPECT_EQ(m.link, LinkState::kSignedOff);
  EXPECT_DOUBLE_EQ(m.last_position.position.x(), 1.2) << "his last known position is the daemon's";
  // His device started again: its own newer position ends the sign-off.
  own.stamp = 50 * kSec;
  tracker.on_position(own, 50 * kSec);
  EXPECT_EQ(member(tracker.evaluate(50 * kSec), "ff3").link, LinkState::kAlive);
}

}  // namespace
}  // namespace sarloc::incident
