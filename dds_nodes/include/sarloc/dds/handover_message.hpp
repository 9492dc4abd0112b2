#pragma once
// A responder's estimator journal (estimator::EstimatorJournal) on the wire: the
// sarloc/rescuer_handover messages core daemons exchange when a responder moves between their
// sectors (docs/architecture.md, "Hand-over between sectors").
#include <string>

#include "sarloc/core/estimator/estimator_journal.hpp"
#include "sarloc/idl/handover.h"

namespace sarloc::dds {

/// Whoever holds `responder_id`'s estimator: hand it to `from_node`.
::sarloc::RescuerHandover handover_request(const std::string& responder_id, const std::string& from_node,
                                           TimestampNs stamp);
/// `from_node` took `responder_id` over from `to_node` (HANDOVER_TAKEN): `to_node` may release it.
::sarloc::RescuerHandover handover_taken(const std::string& responder_id, const std::string& from_node,
                                         const std::string& to_node, TimestampNs stamp);
/// `journal` from `from_node` to `to_node` (HANDOVER_JOURNAL), or HANDOVER_UNAVAILABLE when it
/// overflowed. Throws InputError when it holds more than HANDOVER_ENTRIES_MAX entries or an id
/// the wire refuses.
::sarloc::RescuerHandover handover_journal(const estimator::EstimatorJournal& journal, const std::string& from_node,
                                           const std::string& to_node, TimestampNs stamp);
/// The journal a HANDOVER_JOURNAL carries, checked as every sample from the wire is (to_core).
/// Throws InputError naming the field: an unknown call or role, a call whose sequence ran out,
/// values left over, an entry of another responder.
estimator::EstimatorJournal journal_of(const ::sarloc::RescuerHandover& handover);

}  // namespace sarloc::dds
