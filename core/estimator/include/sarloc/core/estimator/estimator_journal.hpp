#pragma once
// A responder's estimator as the inputs that made it: what a daemon hands another when the
// responder moves to its sector (issue 64, item 4), so that the new daemon takes over from the
// last state instead of starting the search again.
//
// Every estimator is deterministic given its configuration and the calls it took, in order
// (the SOG filter draws nothing; the firefighter's particle filter seeds its generator from the
// responder id and firefighter.seed). So the journal of the calls that changed it, replayed into
// a new estimator of the same role and configuration, gives the same estimator: the same
// estimates and guidance from then on, to the last bit. A snapshot of the state itself would
// need a serialiser for every class of every role (20000 particles, a mixture of up to 1700
// Gaussians, the search's phases), each to be kept in step with the class; the journal needs
// none, at the cost of memory that grows with the search (`max_entries`) and of replaying it at
// the hand-over (docs/architecture.md, "Hand-over between sectors"; docs/benchmarks.md).
//
//   auto journaled = std::make_unique<JournaledEstimator>(make_estimator(role, id, configs), 4096);
//   ... the daemon runs `journaled` as any estimator ...
//   EstimatorJournal handed = journaled->journal();          // old daemon, at the hand-over
//   auto resumed = resume_estimator(handed, configs, 4096);  // new daemon: the same estimator
#include <cstddef>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "sarloc/core/estimator/make_estimator.hpp"

namespace sarloc::estimator {

struct UnknownMotionCall {
  TimestampNs from = 0;
  TimestampNs until = 0;
};
struct CoastCall {
  TimestampNs stamp = 0;
};
struct MarkDoneCall {
  std::uint32_t signal_id = 0;
};
struct LeaveToOthersCall {
  std::set<std::uint32_t> signal_ids;
  TimestampNs until = 0;
};
struct PositionHintCall {
  responder::ResponderPosition own;
};
/// One call that changed the estimator: refused odometry and samples leave it untouched
/// (ResponderEstimator's contract) and are not kept.
using JournalEntry = std::variant<responder::Odometry, UnknownMotionCall, SensorSample, CoastCall, MarkDoneCall,
                                  LeaveToOthersCall, PositionHintCall>;

struct EstimatorJournal {
  ResponderRole role = ResponderRole::kAvalancheRescuer;
  std::string responder_id;
  std::vector<JournalEntry> entries;
  /// More calls came than the journal keeps: it no longer makes the estimator, and
  /// resume_estimator refuses it.
  bool overflowed = false;
};

/// Runs an estimator and keeps the journal of the calls that changed it.
class JournaledEstimator final : public ResponderEstimator {
 public:
  /// `max_entries`: past it the journal is dropped and marked overflowed (the estimator runs on).
  JournaledEstimator(std::unique_ptr<ResponderEstimator> estimator, std::size_t max_entries);

  ResponderRole role() const override { return estimator_->role(); }
  const std::string& responder_id() const override { return estimator_->responder_id(); }
  Outcome add_odometry(const responder::Odometry& odometry) override;
  bool add_unknown_motion(TimestampNs from, TimestampNs until) override;
  Outcome process(const SensorSample& sample) override;
  std::optional<responder::Guidance> coast(TimestampNs stamp) override;
  void mark_done(std::uint32_t signal_id) override;
  void leave_to_others(std::set<std::uint32_t> signal_ids, TimestampNs until) override;
  std::optional<responder::VictimEstimate> estimate_of(std::uint32_t signal_id) const override {
    return estimator_->estimate_of(signal_id);
  }
  std::optional<avalanche::FieldFit> field_fit(std::uint32_t signal_id, const Vec3& field, const Vec3& noise,
                                               std::uint8_t axes) const override {
    return estimator_->field_fit(signal_id, field, noise, axes);
  }
  void hint_position(const responder::ResponderPosition& own) override;
  std::size_t active_filters() const override { return estimator_->active_filters(); }

  const EstimatorJournal& journal() const { return journal_; }

 private:
  void keep(JournalEntry entry);

  std::unique_ptr<ResponderEstimator> estimator_;
  std::size_t max_entries_;
  EstimatorJournal journal_;
};

/// The estimator `journal` made: a new one of its role from `configs`, every entry replayed in
/// order, journaling on (up to `max_entries`). Throws InputError when the journal overflowed,
/// or names the first entry its estimator refuses ("journal of 'r1', entry 17 (a field
/// sample): refused: ..."): the configuration differs from the one that made it.
std::unique_ptr<JournaledEstimator> resume_estimator(const EstimatorJournal& journal, const EstimatorConfigs& configs,
                                                     std::size_t max_entries);

/// How far a journal's calls reach: the end of its motion (odometry or a stand-in), its last
/// processed epoch, and the latest stamp of any call.
struct JournalReach {
  TimestampNs odometry_until = 0;
  std::optional<TimestampNs> measured_at;
  TimestampNs latest = 0;
};
JournalReach reach_of(const EstimatorJournal& journal);

/// A daemon that met the responder before the old daemon's journal arrived has journaled calls
/// of its own (`met`, from a fresh estimator). The journal's estimator, then the calls of `met`
/// the journal does not hold, in order: odometry numbered after its last step, samples numbered
/// after its last of their signal, stand-ins ending after its motion, later coasts and hints, and
/// every mark_done and leave_to_others (idempotent); one the estimator refuses is skipped and
/// counted.
struct MergedEstimator {
  /// Null when `met` numbers the device's steps or a signal's samples afresh (later than the
  /// journal's reach, numbered no higher than the journal's last): the device restarted, its
  /// signals are numbered afresh too, and the journal is not its estimator any more. A restart
  /// that `met` shows neither way (no step nor sample of a known signal yet, or numbered past the
  /// journal's) is not seen: the wire carries no device session.
  std::unique_ptr<JournaledEstimator> estimator;
  std::size_t applied = 0;  ///< calls of `met` applied
  std::size_t skipped = 0;  ///< calls of `met` within the journal's reach, or refused
};
/// Throws as resume_estimator does, for `handed`.
MergedEstimator resume_with_newer(const EstimatorJournal& handed, const EstimatorJournal& met,
                                  const EstimatorConfigs& configs, std::size_t max_entries);

}  // namespace sarloc::estimator
