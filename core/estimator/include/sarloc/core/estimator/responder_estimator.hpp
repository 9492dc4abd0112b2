#pragma once
// The one interface behind which the core daemon (and a responder's device, as its hot
// standby) runs a responder's estimator, whatever the role: samples in; victim estimates,
// guidance and positions out. One instance per responder, used by one thread at a time.
//
//   auto est = make_estimator(ResponderRole::kAvalancheRescuer, "r1", configs);
//   est->add_odometry(odometry);                       // motion, in order
//   auto outcome = est->process(SensorSample{field});  // EstimatorOutput or Rejection
//   if (auto* out = std::get_if<EstimatorOutput>(&outcome)) publish(*out);
//
// The rules that decide when a sample is processed (waiting for its epoch's odometry, unknown
// motion in place of odometry that never came) are SampleSequencer's, not the estimator's.
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "sarloc/core/avalanche/field_fit.hpp"
#include "sarloc/core/estimator/responder_role.hpp"
#include "sarloc/core/estimator/sensor_sample.hpp"
#include "sarloc/core/responder/guidance.hpp"
#include "sarloc/core/responder/odometry.hpp"
#include "sarloc/core/responder/rejection.hpp"
#include "sarloc/core/responder/responder_candidates.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/core/responder/victim_estimate.hpp"

namespace sarloc::estimator {

/// What one accepted sample produced (any part may be empty).
struct EstimatorOutput {
  std::vector<responder::VictimEstimate> estimates;   ///< relative to the responder
  std::optional<responder::Guidance> guidance;        ///< where to go next
  std::optional<responder::ResponderPosition> position;  ///< where the responder is (incident frame)
  /// The places of an ambiguous position; once with none when the ambiguity ends.
  std::optional<responder::ResponderCandidates> candidates;
};

using Outcome = std::variant<EstimatorOutput, responder::Rejection>;

class ResponderEstimator {
 public:
  virtual ~ResponderEstimator() = default;

  virtual ResponderRole role() const = 0;
  virtual const std::string& responder_id() const = 0;

  /// Motion since the previous odometry. A rejection leaves the estimator untouched.
  virtual Outcome add_odometry(const responder::Odometry& odometry) = 0;
  /// Odometry over [from, until] never came: stand in motion of unknown direction (see
  /// avalanche::RescuerSearch::add_unknown_motion). Returns false when it did nothing.
  virtual bool add_unknown_motion(TimestampNs from, TimestampNs until) = 0;
  /// One sensor sample. A rejection leaves the estimator untouched.
  virtual Outcome process(const SensorSample& sample) = 0;

  /// Guidance for an epoch in which nothing was measured (the target not heard): from the
  /// belief moved by the odometry since. nullopt without a target.
  virtual std::optional<responder::Guidance> coast(TimestampNs stamp) = 0;
  /// The victim behind `signal_id` was found (here or as incident command reports): stop
  /// guiding to it.
  virtual void mark_done(std::uint32_t signal_id) = 0;
  /// These signals' victims are pursued by other responders (incident command's search plan):
  /// do not guide to them while in the set, until a sample is stamped after `until`; it
  /// replaces the previous one (avalanche::RescuerSearch::leave_to_others).
  virtual void leave_to_others(std::set<std::uint32_t> signal_ids, TimestampNs until) = 0;
  /// Latest estimate of a victim signal, in the current frame (nullopt if never measured).
  virtual std::optional<responder::VictimEstimate> estimate_of(std::uint32_t signal_id) const = 0;
  /// How well a beacon field sample would fit a signal's filter, without updating it: the
  /// device's signal separation asks when carrier and timing cannot decide
  /// (avalanche::SignalSeparator::set_consistency). nullopt for a signal without a filter or
  /// a role that has none.
  virtual std::optional<avalanche::FieldFit> field_fit(std::uint32_t /*signal_id*/, const Vec3& /*field*/,
                                                       const Vec3& /*noise*/, std::uint8_t /*axes*/) const {
    return std::nullopt;
  }
  /// The responder's device's own position (its dead reckoning, as it publishes it): a start for
  /// an estimator that meets the responder mid-search. Ignored by roles that need none.
  virtual void hint_position(const responder::ResponderPosition& /*own*/) {}
  /// Filters alive (NodeStatus.active_filters).
  virtual std::size_t active_filters() const = 0;
};

}  // namespace sarloc::estimator
