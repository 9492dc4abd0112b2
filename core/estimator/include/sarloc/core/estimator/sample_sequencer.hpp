#pragma once
// When a responder's samples are processed: the daemon's sequencing rules, apart from DDS.
//
// Odometry and sensor samples travel on different topics, so a sample of a new epoch can
// arrive before the odometry up to its stamp. SampleSequencer (one per responder, one thread)
//   1. applies odometry at once, and remembers how far the responder's motion is known
//      (odometry_until): accepted steps, and steps refused only for their values (their
//      timing still says how far the clock went; refused timing moves nothing);
//   2. holds a sample of a new epoch until odometry covers its stamp, at most odometry_wait
//      (wall); samples behind a held one wait too, so they stay in order;
//   3. when the wait expires, stands unknown motion in for the missing odometry
//      (ResponderEstimator::add_unknown_motion) before processing: processing as if the
//      responder had stood still let one near-field sample lock a filter 10 m off under 20 %
//      packet loss. The late odometry is refused when it arrives (kSuperseded);
//   4. leaves refusing late or superseded samples to the estimator's own gate.
// What happened is appended to a SequencerReport: answers to publish, rejections and
// anomalies to count.
//
//   SampleSequencer seq(make_estimator(role, id, configs), std::chrono::milliseconds(250));
//   SequencerReport report;
//   seq.on_odometry(odo, report);
//   seq.on_sample(sample, now, report);
//   seq.release(now, report);              // whenever time passes (next_deadline())
#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/estimator/responder_estimator.hpp"

namespace sarloc::estimator {

struct SequencerReport {
  struct Answer {
    EstimatorOutput output;
    std::uint64_t sequence = 0;  ///< of the sample it answers
  };
  std::vector<Answer> answers;
  std::vector<responder::Rejection> rejections;
  std::size_t accepted = 0;                 ///< samples and odometry taken by the estimator
  struct OdometryLate {
    std::string rescuer_id;
    std::string detail;
  };
  std::vector<OdometryLate> odometry_late;  ///< one per sample processed without its odometry
};

class SampleSequencer {
 public:
  using Clock = std::chrono::steady_clock;

  /// odometry_wait = 0 processes every sample at once.
  SampleSequencer(std::unique_ptr<ResponderEstimator> estimator, Clock::duration odometry_wait);

  void on_odometry(const responder::Odometry& odometry, SequencerReport& report);
  void on_sample(const SensorSample& sample, Clock::time_point now, SequencerReport& report);
  /// Processes the held samples whose odometry arrived or whose wait expired by `now`.
  void release(Clock::time_point now, SequencerReport& report);
  /// When release() next has something to do because a wait expires (nullopt: nothing held).
  std::optional<Clock::time_point> next_deadline() const;

  /// Runs `estimator` from now on (one resumed from another daemon's journal,
  /// estimator_journal.hpp), whose calls reach `odometry_until` and `measured_at`; the samples
  /// held stay held for it.
  void replace_estimator(std::unique_ptr<ResponderEstimator> estimator, TimestampNs odometry_until,
                         std::optional<TimestampNs> measured_at);

  ResponderEstimator& estimator() { return *estimator_; }
  const ResponderEstimator& estimator() const { return *estimator_; }
  std::size_t held() const { return held_.size(); }
  /// How far the responder's motion is known (the interval_end of the odometry dealt with).
  TimestampNs odometry_until() const { return odometry_until_; }

 private:
  struct Held {
    SensorSample sample;
    Clock::time_point deadline;
  };
  void process(const SensorSample& sample, SequencerReport& report);

  std::unique_ptr<ResponderEstimator> estimator_;
  Clock::duration odometry_wait_;
  TimestampNs odometry_until_ = 0;            ///< interval_end of the last odometry dealt with
  std::optional<TimestampNs> measured_at_;    ///< stamp of the last processed epoch
  std::deque<Held> held_;                     ///< waiting for their odometry, in arrival order
};

}  // namespace sarloc::estimator
