// A responder's estimator journal on the wire (sarloc/rescuer_handover): what the new daemon
// reads back makes the same estimator, and a message that does not add up is refused by name.
#include "sarloc/dds/handover_message.hpp"

#include <gtest/gtest.h>

#include "sarloc/core/common/errors.hpp"
#include "support/journaled_search.hpp"

namespace sarloc::dds {
namespace {

using estimator::EstimatorJournal;
using estimator::JournaledEstimator;

// A rescuer's search of 40 epochs with the realistic receiver, and every other kind of call.
EstimatorJournal search_journal() {
  return test::journaled_search(11, 40, [](int epoch, JournaledEstimator& journaled, TimestampNs now) {
    if (epoch == 10) journaled.add_unknown_motion(now, now + 500'000'000);
    if (epoch == 12) journaled.leave_to_others({7, 9}, now + 1'000'000'000);
    if (epoch == 14) journaled.mark_done(7);
    if (epoch == 15) {
      responder::ResponderPosition own;
      own.responder_id = "r1";
      own.team_id = "north";
      own.stamp = now;
      own.position.position = Vec3(3.0, -4.0, 1.5);
      own.source = responder::PositionSource::kGnss;
      journaled.hint_position(own);
    }
  });
}

TEST(HandoverMessage, AJournalReadBackFromTheWireMakesTheSameEstimator) {
  const EstimatorJournal journal = search_journal();
  const auto message = handover_journal(journal, "core-west", "core-east", 42);
  EXPECT_EQ(message.kind(), ::sarloc::HANDOVER_JOURNAL);
  EXPECT_EQ(message.calls().size(), journal.entries.size());
  EXPECT_EQ(message.unknown_motion().size(), 1U);
  EXPECT_EQ(message.leaves().size(), 1U);
  EXPECT_EQ(message.done_signals().size(), 1U);
  EXPECT_EQ(message.position_hints().size(), 1U);
  EXPECT_GT(message.field_measurements().size(), 20U);
  const EstimatorJournal read = journal_of(message);
  ASSERT_EQ(read.entries.size(), journal.entries.size());
  for (std::size_t i = 0; i < read.entries.size(); ++i) EXPECT_EQ(read.entries[i].index(), journal.entries[i].index());

  const estimator::EstimatorConfigs configs;
  const auto sent = estimator::resume_estimator(journal, configs, 100000);
  const auto received = estimator::resume_estimator(read, configs, 100000);
  ASSERT_EQ(sent->active_filters(), received->active_filters());
  ASSERT_GT(sent->active_filters(), 0U);
  for (std::uint32_t signal = 0; signal < 8; ++signal) {
    const auto a = sent->estimate_of(signal);
    const auto b = received->estimate_of(signal);
    ASSERT_EQ(a.has_value(), b.has_value()) << "signal " << signal;
    if (!a) continue;
    EXPECT_EQ(a->relative.position, b->relative.position) << "signal " << signal;
    EXPECT_EQ(a->relative.covariance, b->relative.covariance) << "signal " << signal;
    EXPECT_EQ(a->status, b->status);
  }
}

TEST(HandoverMessage, AnOverflowedJournalIsSentAsUnavailableAndARequestCarriesNothing) {
  EstimatorJournal journal;
  journal.responder_id = "r1";
  journal.overflowed = true;
  const auto message = handover_journal(journal, "core-west", "core-east", 42);
  EXPECT_EQ(message.kind(), ::sarloc::HANDOVER_UNAVAILABLE);
  EXPECT_TRUE(message.calls().empty());
  EXPECT_THROW(journal_of(message), InputError);
  const auto request = handover_request("r1", "core-east", 42);
  EXPECT_EQ(request.kind(), ::sarloc::HANDOVER_REQUEST);
  EXPECT_EQ(request.to_node().to_string(), "");
}

TEST(HandoverMessage, AMessageThatDoesNotAddUpIsRefusedNamingTheField) {
  const auto message = handover_journal(search_journal(), "core-west", "core-east", 42);
  const auto refused = [](const ::sarloc::RescuerHandover& m, const std::string& expected) {
    try {
      journal_of(m);
      ADD_FAILURE() << "expected a refusal mentioning '" << expected << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  auto short_of_odometry = message;
  short_of_odometry.odometry_steps().pop_back();
  refused(short_of_odometry, "rescuer_handover.odometry_steps: the calls name more than");
  auto left_over = message;
  left_over.coasts().push_back(7);
  refused(left_over, "left over");
  auto unknown_call = message;
  unknown_call.calls()[3] = 99;
  refused(unknown_call, "rescuer_handover.calls: 99 is no journal call");
  auto bad_role = message;
  bad_role.role(7);
  refused(bad_role, "rescuer_handover.role = 7");
  auto someone_else = message;
  someone_else.odometry_steps()[0].rescuer_id("r2");
  refused(someone_else, "an entry of 'r2' in the journal of 'r1'");
  auto bad_id = message;
  bad_id.responder_id("r1<script>");
  refused(bad_id, "rescuer_handover.responder_id");
}

}  // namespace
}  // namespace sarloc::dds
