#include "sarloc/core/estimator/sample_sequencer.hpp"

#include <algorithm>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::estimator {
namespace {

using responder::RejectReason;

// A refused step may close at most this far past the last epoch (its stamp is untrusted too).
constexpr TimestampNs kMaxEpochGapNs = 60'000'000'000;

}  // namespace

SampleSequencer::SampleSequencer(std::unique_ptr<ResponderEstimator> estimator, Clock::duration odometry_wait)
    : estimator_(std::move(estimator)), odometry_wait_(std::max(odometry_wait, Clock::duration::zero())) {
  if (!estimator_) throw ConfigError("SampleSequencer: no estimator");
}

void SampleSequencer::on_odometry(const responder::Odometry& odometry, SequencerReport& report) {
  auto outcome = estimator_->add_odometry(odometry);
  if (auto* rejected = std::get_if<responder::Rejection>(&outcome)) {
    // A step refused for its values still says how far the responder's clock went: waiting
    // for it would only make the next epoch late. Refused timing moves nothing.
    const bool timing_ok = rejected->reason == RejectReason::kAbsurdMotion || rejected->reason == RejectReason::kInvalidValue;
    if (timing_ok && odometry.interval_end > odometry_until_ &&
        (!measured_at_ || odometry.interval_end <= *measured_at_ + kMaxEpochGapNs)) {
      odometry_until_ = odometry.interval_end;
    }
    report.rejections.push_back(std::move(*rejected));
    return;
  }
  ++report.accepted;
  odometry_until_ = std::max(odometry_until_, odometry.interval_end);
  auto& output = std::get<EstimatorOutput>(outcome);
  if (!output.estimates.empty() || output.guidance || output.position) {
    report.answers.push_back({std::move(output), odometry.sequence});
  }
}

void SampleSequencer::on_sample(const SensorSample& sample, Clock::time_point now, SequencerReport& report) {
  // A new epoch follows a step: wait for the odometry up to its stamp. The other samples of an
  // epoch already processed share its stamp and need nothing more.
  const TimestampNs stamp = stamp_of(sample);
  const bool new_epoch = measured_at_ && stamp > *measured_at_;
  const bool motion_pending = new_epoch && stamp > odometry_until_;
  if ((motion_pending || !held_.empty()) && odometry_wait_ > Clock::duration::zero()) {
    held_.push_back(Held{sample, now + odometry_wait_});
    return;
  }
  process(sample, report);
}

void SampleSequencer::release(Clock::time_point now, SequencerReport& report) {
  while (!held_.empty()) {
    const Held& front = held_.front();
    const TimestampNs stamp = stamp_of(front.sample);
    const bool covered = stamp <= odometry_until_;
    if (!covered && now < front.deadline) return;
    if (!covered) {
      const TimestampNs from = odometry_until_ > 0 ? odometry_until_ : measured_at_.value_or(0);
      bool stood_in = false;
      try {
        stood_in = estimator_->add_unknown_motion(from, stamp);
      } catch (const InputError&) {  // the covariance is built valid; never let it stop a worker
      }
      if (stood_in) odometry_until_ = stamp;
      const std::string& id = estimator_->responder_id();
      report.odometry_late.push_back({id, "rescuer '" + id + "': no odometry up to stamp " + std::to_string(stamp) +
                                              " within odometry_wait_s: processed " +
                                              (stood_in ? "with unknown motion in its place"
                                                        : "without it (no stand-in for this gap)")});
    }
    const SensorSample sample = front.sample;
    held_.pop_front();
    process(sample, report);
  }
}

void SampleSequencer::replace_estimator(std::unique_ptr<ResponderEstimator> estimator, TimestampNs odometry_until,
                                        std::optional<TimestampNs> measured_at) {
  if (!estimator) throw ConfigError("SampleSequencer: no estimator");
  estimator_ = std::move(estimator);
  odometry_until_ = std::max(odometry_until_, odometry_until);
  if (measured_at) measured_at_ = std::max(measured_at_.value_or(*measured_at), *measured_at);
}

std::optional<SampleSequencer::Clock::time_point> SampleSequencer::next_deadline() const {
  if (held_.empty()) return std::nullopt;
  return held_.front().deadline;
}

void SampleSequencer::process(const SensorSample& sample, SequencerReport& report) {
  auto outcome = estimator_->process(sample);
  if (auto* rejected = std::get_if<responder::Rejection>(&outcome)) {
    report.rejections.push_back(std::move(*rejected));
    return;
  }
  ++report.accepted;
  const TimestampNs stamp = stamp_of(sample);
  measured_at_ = std::max(measured_at_.value_or(stamp), stamp);
  report.answers.push_back({std::move(std::get<EstimatorOutput>(outcome)), sequence_of(sample)});
}

}  // namespace sarloc::estimator
