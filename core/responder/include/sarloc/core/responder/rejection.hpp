#pragma once
// Why a responder's sample was refused. The names are stable: NodeStatus.rejects counts them
// and operators grep logs for them (docs/operations.md).
#include <cstdint>
#include <string>

namespace sarloc::responder {

enum class RejectReason : std::uint8_t {
  kInvalidValue,       ///< non-finite, absurd magnitude, non-PD covariance (filter's validation)
  kWrongRescuer,       ///< sample for another rescuer reached this estimator
  kDuplicateSequence,  ///< sequence number already seen
  kSequenceBackwards,  ///< sequence number lower than the last accepted
  kStampBackwards,     ///< timestamp not after the last accepted one (or absurdly far after it)
  kTooManySignals,     ///< more separated signals than the estimator tracks
  kAbsurdMotion,       ///< odometry step or rotation beyond the limits
  kSuperseded,         ///< odometry arrived after unknown motion stood in for its interval
  kLateMeasurement,    ///< sample older than the odometry already received (overtaken)
  kWrongRole,          ///< a sample of a kind this responder's role does not use
};

const char* to_string(RejectReason reason);

struct Rejection {
  RejectReason reason = RejectReason::kInvalidValue;
  std::string detail;       ///< names the responder, the field and the value
  std::string rescuer_id;   ///< whose sample (for per-responder rate-limited logs)
};

/// A rejection whose detail starts with the responder ("rescuer 'r1': <what>").
Rejection reject(RejectReason reason, const std::string& rescuer_id, const std::string& what);

}  // namespace sarloc::responder
