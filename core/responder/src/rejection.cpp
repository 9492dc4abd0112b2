#include "sarloc/core/responder/rejection.hpp"

namespace sarloc::responder {

const char* to_string(RejectReason reason) {
  switch (reason) {
    case RejectReason::kInvalidValue: return "invalid_value";
    case RejectReason::kWrongRescuer: return "wrong_rescuer";
    case RejectReason::kDuplicateSequence: return "duplicate_sequence";
    case RejectReason::kSequenceBackwards: return "sequence_backwards";
    case RejectReason::kStampBackwards: return "stamp_backwards";
    case RejectReason::kTooManySignals: return "too_many_signals";
    case RejectReason::kAbsurdMotion: return "absurd_motion";
    case RejectReason::kSuperseded: return "superseded";
    case RejectReason::kLateMeasurement: return "late_measurement";
    case RejectReason::kWrongRole: return "wrong_role";
  }
  return "unknown";
}

Rejection reject(RejectReason reason, const std::string& rescuer_id, const std::string& what) {
  return Rejection{reason, "rescuer '" + rescuer_id + "': " + what, rescuer_id};
}

}  // namespace sarloc::responder
