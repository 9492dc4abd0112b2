// SampleSequencer: when a responder's samples are processed, with a scripted estimator that
// records every call (no filter, no DDS).
#include "sarloc/core/estimator/sample_sequencer.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::estimator {
namespace {

using Clock = SampleSequencer::Clock;
using namespace std::chrono_literals;

constexpr TimestampNs kSecond = 1'000'000'000;

// Records calls in order; refuses odometry whose sequence is in refuse_odometry.
class RecordingEstimator final : public ResponderEstimator {
 public:
  explicit RecordingEstimator(std::vector<std::string>* log) : log_(log) {}
  std::map<std::uint64_t, responder::RejectReason> refuse_odometry;
  std::set<std::uint64_t> refuse_samples;

  ResponderRole role() const override { return ResponderRole::kAvalancheRescuer; }
  const std::string& responder_id() const override { return id_; }
  Outcome add_odometry(const responder::Odometry& o) override {
    if (auto it = refuse_odometry.find(o.sequence); it != refuse_odometry.end()) {
      log_->push_back("refused odometry " + std::to_string(o.sequence));
      return responder::Rejection{it->second, "refused", "r1"};
    }
    log_->push_back("odometry " + std::to_string(o.sequence));
    return EstimatorOutput{};
  }
  bool add_unknown_motion(TimestampNs from, TimestampNs until) override {
    log_->push_back("unknown " + std::to_string(from / kSecond) + "-" + std::to_string(until / kSecond));
    return true;
  }
  Outcome process(const SensorSample& s) override {
    if (refuse_samples.count(sequence_of(s)) != 0) {
      log_->push_back("refused sample " + std::to_string(sequence_of(s)));
      return responder::Rejection{responder::RejectReason::kStampBackwards, "refused", "r1"};
    }
    log_->push_back("sample " + std::to_string(sequence_of(s)));
    EstimatorOutput out;
    out.estimates.emplace_back();
    return out;
  }
  std::optional<responder::Guidance> coast(TimestampNs) override { return std::nullopt; }
  void mark_done(std::uint32_t) override {}
  void leave_to_others(std::set<std::uint32_t>, TimestampNs) override {}
  std::optional<responder::VictimEstimate> estimate_of(std::uint32_t) const override { return std::nullopt; }
  std::size_t active_filters() const override { return 0; }

 private:
  std::string id_ = "r1";
  std::vector<std::string>* log_;
};

SensorSample sample(std::uint64_t sequence, TimestampNs stamp_s, std::uint32_t signal = 1) {
  avalanche::FieldMeasurement m;
  m.rescuer_id = "r1";
  m.signal_id = signal;
  m.sequence = sequence;
  m.stamp = stamp_s * kSecond;
  return m;
}

responder::Odometry odometry(std::uint64_t sequence, TimestampNs from_s, TimestampNs until_s) {
  responder::Odometry o;
  o.rescuer_id = "r1";
  o.sequence = sequence;
  o.interval_start = from_s * kSecond;
  o.interval_end = until_s * kSecond;
  return o;
}

struct Fixture : ::testing::Test {
  std::vector<std::string> log;
  RecordingEstimator* estimator = nullptr;
  std::unique_ptr<SampleSequencer> seq;
  Clock::time_point t0 = Clock::now();
  SequencerReport report;

  void make(Clock::duration wait = 250ms) {
    auto e = std::make_unique<RecordingEstimator>(&log);
    estimator = e.get();
    seq = std::make_unique<SampleSequencer>(std::move(e), wait);
  }
};

TEST_F(Fixture, FirstEpochIsProcessedAtOnce) {
  make();
  seq->on_sample(sample(1, 10), t0, report);
  EXPECT_EQ(log, (std::vector<std::string>{"sample 1"}));
  ASSERT_EQ(report.answers.size(), 1U);
  EXPECT_EQ(report.answers[0].sequence, 1U);
  EXPECT_EQ(report.accepted, 1U);
}

TEST_F(Fixture, NewEpochWaitsForItsOdometryThenMotionComesFirst) {
  make();
  seq->on_sample(sample(1, 10), t0, report);
  seq->on_sample(sample(2, 11), t0, report);  // arrived before the step 10 -> 11
  EXPECT_EQ(seq->held(), 1U);
  ASSERT_TRUE(seq->next_deadline().has_value());
  EXPECT_EQ(*seq->next_deadline(), t0 + 250ms);
  seq->release(t0 + 10ms, report);
  EXPECT_EQ(seq->held(), 1U) << "neither covered nor expired";
  seq->on_odometry(odometry(1, 10, 11), report);
  seq->release(t0 + 20ms, report);
  EXPECT_EQ(log, (std::vector<std::string>{"sample 1", "odometry 1", "sample 2"}));
  EXPECT_TRUE(report.odometry_late.empty());
}

TEST_F(Fixture, OtherSignalsOfAnEpochAlreadyProcessedNeedNothing) {
  make();
  seq->on_sample(sample(1, 10, 1), t0, report);
  seq->on_sample(sample(1, 10, 2), t0, report);
  EXPECT_EQ(seq->held(), 0U);
  EXPECT_EQ(log.size(), 2U);
}

TEST_F(Fixture, ExpiredWaitStandsInUnknownMotionBeforeTheSample) {
  make();
  seq->on_odometry(odometry(1, 9, 10), report);
  seq->on_sample(sample(1, 10), t0, report);
  seq->on_sample(sample(2, 12), t0, report);
  seq->release(t0 + 300ms, report);
  EXPECT_EQ(log, (std::vector<std::string>{"odometry 1", "sample 1", "unknown 10-12", "sample 2"}));
  ASSERT_EQ(report.odometry_late.size(), 1U);
  EXPECT_EQ(report.odometry_late[0].rescuer_id, "r1");
  EXPECT_NE(report.odometry_late[0].detail.find("unknown motion in its place"), std::string::npos);
  // The late step arrives now: the estimator's own gate refuses it (kSuperseded); the
  // sequencer passes it on and does not wait on it again.
  seq->on_sample(sample(3, 13), t0 + 400ms, report);
  EXPECT_EQ(seq->held(), 1U);
}

TEST_F(Fixture, SamplesBehindAHeldOneWaitInOrder) {
  make();
  seq->on_sample(sample(1, 10, 1), t0, report);
  seq->on_sample(sample(2, 11, 1), t0, report);
  seq->on_sample(sample(2, 11, 2), t0, report);  // same epoch, other signal: behind the first
  EXPECT_EQ(seq->held(), 2U);
  seq->on_odometry(odometry(1, 10, 11), report);
  seq->release(t0, report);
  EXPECT_EQ(log, (std::vector<std::string>{"sample 1", "odometry 1", "sample 2", "sample 2"}));
}

TEST_F(Fixture, OdometryRefusedForItsValuesStillMovesTheClock) {
  make();
  seq->on_sample(sample(1, 10), t0, report);
  estimator->refuse_odometry[1] = responder::RejectReason::kAbsurdMotion;
  seq->on_odometry(odometry(1, 10, 11), report);
  ASSERT_EQ(report.rejections.size(), 1U);
  seq->on_sample(sample(2, 11), t0, report);
  EXPECT_EQ(seq->held(), 0U) << "the refused step still covered stamp 11: no wait";
}

TEST_F(Fixture, OdometryRefusedForItsTimingMovesNothing) {
  make();
  seq->on_sample(sample(1, 10), t0, report);
  estimator->refuse_odometry[1] = responder::RejectReason::kStampBackwards;
  seq->on_odometry(odometry(1, 10, 11), report);
  seq->on_sample(sample(2, 11), t0, report);
  EXPECT_EQ(seq->held(), 1U);
}

TEST_F(Fixture, ZeroWaitProcessesAtOnce) {
  make(Clock::duration::zero());
  seq->on_sample(sample(1, 10), t0, report);
  seq->on_sample(sample(2, 11), t0, report);
  EXPECT_EQ(seq->held(), 0U);
  EXPECT_EQ(log, (std::vector<std::string>{"sample 1", "sample 2"}));
}

TEST_F(Fixture, RefusedSampleIsReportedAndDoesNotStartAnEpoch) {
  make();
  estimator->refuse_samples.insert(1);
  seq->on_sample(sample(1, 10), t0, report);
  EXPECT_EQ(report.rejections.size(), 1U);
  EXPECT_TRUE(report.answers.empty());
  seq->on_sample(sample(2, 11), t0, report);
  EXPECT_EQ(seq->held(), 0U) << "no epoch was processed yet, so nothing to wait for";
}

TEST(SampleSequencer, RefusesToRunWithoutAnEstimator) {
  EXPECT_THROW(SampleSequencer(nullptr, 250ms), ConfigError);
}

}  // namespace
}  // namespace sarloc::estimator
