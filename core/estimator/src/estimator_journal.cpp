#include "sarloc/core/estimator/estimator_journal.hpp"

#include <algorithm>
#include <map>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::estimator {
namespace {

const char* name_of(const JournalEntry& entry) {
  static constexpr const char* kNames[] = {"odometry",  "unknown motion",  "a sensor sample", "a coast",
                                           "mark done", "leave to others", "a position hint"};
  return kNames[entry.index()];
}

// The stamp a call carries (nullopt: mark_done and leave_to_others carry none).
std::optional<TimestampNs> stamp_of_call(const JournalEntry& entry) {
  if (const auto* odometry = std::get_if<responder::Odometry>(&entry)) return odometry->interval_end;
  if (const auto* motion = std::get_if<UnknownMotionCall>(&entry)) return motion->until;
  if (const auto* sample = std::get_if<SensorSample>(&entry)) return stamp_of(*sample);
  if (const auto* coast = std::get_if<CoastCall>(&entry)) return coast->stamp;
  if (const auto* hint = std::get_if<PositionHintCall>(&entry)) return hint->own.stamp;
  return std::nullopt;
}

// Replays one entry into `estimator`; returns the refusal, if any.
std::optional<std::string> replay(JournaledEstimator& estimator, const JournalEntry& entry) {
  const auto refusal = [](const Outcome& outcome) -> std::optional<std::string> {
    if (const auto* rejection = std::get_if<responder::Rejection>(&outcome)) {
      return std::string("refused: ") + responder::to_string(rejection->reason) + ": " + rejection->detail;
    }
    return std::nullopt;
  };
  if (const auto* odometry = std::get_if<responder::Odometry>(&entry))
    return refusal(estimator.add_odometry(*odometry));
  if (const auto* motion = std::get_if<UnknownMotionCall>(&entry)) {
    if (!estimator.add_unknown_motion(motion->from, motion->until)) return std::string("did nothing");
    return std::nullopt;
  }
  if (const auto* sample = std::get_if<SensorSample>(&entry)) return refusal(estimator.process(*sample));
  if (const auto* coast = std::get_if<CoastCall>(&entry)) {
    estimator.coast(coast->stamp);
  } else if (const auto* done = std::get_if<MarkDoneCall>(&entry)) {
    estimator.mark_done(done->signal_id);
  } else if (const auto* leave = std::get_if<LeaveToOthersCall>(&entry)) {
    estimator.leave_to_others(leave->signal_ids, leave->until);
  } else if (const auto* hint = std::get_if<PositionHintCall>(&entry)) {
    estimator.hint_position(hint->own);
  }
  return std::nullopt;
}

}  // namespace

JournaledEstimator::JournaledEstimator(std::unique_ptr<ResponderEstimator> estimator, std::size_t max_entries)
    : estimator_(std::move(estimator)), max_entries_(max_entries) {
  if (!estimator_) throw ConfigError("JournaledEstimator: no estimator");
  journal_.role = estimator_->role();
  journal_.responder_id = estimator_->responder_id();
}

void JournaledEstimator::keep(JournalEntry entry) {
  if (journal_.overflowed) return;
  if (journal_.entries.size() >= max_entries_) {
    journal_.overflowed = true;
    journal_.entries.clear();
    journal_.entries.shrink_to_fit();
    return;
  }
  journal_.entries.push_back(std::move(entry));
}

Outcome JournaledEstimator::add_odometry(const responder::Odometry& odometry) {
  Outcome outcome = estimator_->add_odometry(odometry);
  if (std::holds_alternative<EstimatorOutput>(outcome)) keep(odometry);
  return outcome;
}

bool JournaledEstimator::add_unknown_motion(TimestampNs from, TimestampNs until) {
  const bool moved = estimator_->add_unknown_motion(from, until);
  if (moved) keep(UnknownMotionCall{from, until});
  return moved;
}

Outcome JournaledEstimator::process(const SensorSample& sample) {
  Outcome outcome = estimator_->process(sample);
  if (std::holds_alternative<EstimatorOutput>(outcome)) keep(sample);
  return outcome;
}

std::optional<responder::Guidance> JournaledEstimator::coast(TimestampNs stamp) {
  keep(CoastCall{stamp});
  return estimator_->coast(stamp);
}

void JournaledEstimator::mark_done(std::uint32_t signal_id) {
  keep(MarkDoneCall{signal_id});
  estimator_->mark_done(signal_id);
}

void JournaledEstimator::leave_to_others(std::set<std::uint32_t> signal_ids, TimestampNs until) {
  keep(LeaveToOthersCall{signal_ids, until});
  estimator_->leave_to_others(std::move(signal_ids), until);
}

void JournaledEstimator::hint_position(const responder::ResponderPosition& own) {
  keep(PositionHintCall{own});
  estimator_->hint_position(own);
}

std::unique_ptr<JournaledEstimator> resume_estimator(const EstimatorJournal& journal, const EstimatorConfigs& configs,
                                                     std::size_t max_entries) {
  const std::string who = "journal of '" + journal.responder_id + "'";
  if (journal.overflowed) {
    throw InputError(who + ": overflowed (more calls than the old daemon kept): it no longer makes the estimator");
  }
  auto resumed =
      std::make_unique<JournaledEstimator>(make_estimator(journal.role, journal.responder_id, configs), max_entries);
  for (std::size_t i = 0; i < journal.entries.size(); ++i) {
    const JournalEntry& entry = journal.entries[i];
    if (const auto refused = replay(*resumed, entry)) {
      throw InputError(who + ", entry " + std::to_string(i) + " (" + name_of(entry) + "): " + *refused +
                       ": the configuration differs from the one that made it");
    }
  }
  return resumed;
}

JournalReach reach_of(const EstimatorJournal& journal) {
  JournalReach reach;
  for (const auto& entry : journal.entries) {
    if (const auto* odometry = std::get_if<responder::Odometry>(&entry)) {
      reach.odometry_until = std::max(reach.odometry_until, odometry->interval_end);
    } else if (const auto* motion = std::get_if<UnknownMotionCall>(&entry)) {
      reach.odometry_until = std::max(reach.odometry_until, motion->until);
    } else if (const auto* sample = std::get_if<SensorSample>(&entry)) {
      reach.measured_at = std::max(reach.measured_at.value_or(stamp_of(*sample)), stamp_of(*sample));
    }
    if (const auto stamp = stamp_of_call(entry)) reach.latest = std::max(reach.latest, *stamp);
  }
  return reach;
}

MergedEstimator resume_with_newer(const EstimatorJournal& handed, const EstimatorJournal& met,
                                  const EstimatorConfigs& configs, std::size_t max_entries) {
  // What of `met` the journal has already: calls are told apart by their own numbering, not by
  // stamps (an epoch's samples carry the stamp its odometry ends at).
  std::optional<std::uint64_t> last_step;
  std::map<std::uint32_t, std::uint64_t> last_sample;  // per signal
  std::optional<TimestampNs> last_coast, last_hint;
  const JournalReach reach = reach_of(handed);
  const TimestampNs motion_until = reach.odometry_until;
  for (const auto& entry : handed.entries) {
    if (const auto* odometry = std::get_if<responder::Odometry>(&entry)) {
      last_step = std::max(last_step.value_or(0), odometry->sequence);
    } else if (const auto* sample = std::get_if<SensorSample>(&entry)) {
      auto& last = last_sample[signal_of(*sample)];
      last = std::max(last, sequence_of(*sample));
    } else if (const auto* coast = std::get_if<CoastCall>(&entry)) {
      last_coast = std::max(last_coast.value_or(coast->stamp), coast->stamp);
    } else if (const auto* hint = std::get_if<PositionHintCall>(&entry)) {
      last_hint = std::max(last_hint.value_or(hint->own.stamp), hint->own.stamp);
    }
  }
  const auto newer = [&](const JournalEntry& entry) {
    if (const auto* odometry = std::get_if<responder::Odometry>(&entry)) {
      return !last_step || odometry->sequence > *last_step;
    }
    if (const auto* motion = std::get_if<UnknownMotionCall>(&entry)) return motion->until > motion_until;
    if (const auto* sample = std::get_if<SensorSample>(&entry)) {
      const auto last = last_sample.find(signal_of(*sample));
      return last == last_sample.end() || sequence_of(*sample) > last->second;
    }
    if (const auto* coast = std::get_if<CoastCall>(&entry)) return !last_coast || coast->stamp > *last_coast;
    if (const auto* hint = std::get_if<PositionHintCall>(&entry)) return !last_hint || hint->own.stamp > *last_hint;
    return true;  // mark_done, leave_to_others: idempotent, the latest wins
  };
  MergedEstimator merged;
  for (const auto& entry : met.entries) {
    // A later step, or a later sample of a signal, numbered no higher: the device restarted.
    const auto* odometry = std::get_if<responder::Odometry>(&entry);
    if (odometry != nullptr && last_step && odometry->interval_end > motion_until && odometry->sequence <= *last_step) {
      return merged;
    }
    const auto* sample = std::get_if<SensorSample>(&entry);
    if (sample != nullptr && stamp_of(*sample) > reach.latest) {
      const auto last = last_sample.find(signal_of(*sample));
      if (last != last_sample.end() && sequence_of(*sample) <= last->second) return merged;
    }
  }
  merged.estimator = resume_estimator(handed, configs, max_entries);
  for (const auto& entry : met.entries) {
    if (!newer(entry) || replay(*merged.estimator, entry)) {
      ++merged.skipped;
    } else {
      ++merged.applied;
    }
  }
  return merged;
}

}  // namespace sarloc::estimator
