#include "sarloc/dds/handover_message.hpp"

#include <variant>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/identifier.hpp"
#include "sarloc/dds/conversions.hpp"

namespace sarloc::dds {
namespace {

// RescuerHandover.calls holds each entry's index in estimator::JournalEntry: JOURNAL_ODOMETRY 0
// ... JOURNAL_POSITION_HINT 6, in the variant's order.
static_assert(std::variant_size_v<estimator::JournalEntry> == ::sarloc::JOURNAL_POSITION_HINT + 1);

void check_id_fits(const std::string& id, const char* field) {
  if (id.size() > ::sarloc::ID_MAX) {
    throw InputError(std::string("rescuer_handover.") + field + ": " + std::to_string(id.size()) +
                     " characters, at most " + std::to_string(::sarloc::ID_MAX));
  }
}

// Takes a kind's next value, or refuses a journal whose calls name more of them than it carries.
template <class Sequence>
const typename Sequence::value_type& next(const Sequence& sequence, std::size_t& taken, const char* field) {
  if (taken >= sequence.size()) {
    throw InputError(std::string("rescuer_handover.") + field + ": the calls name more than its " +
                     std::to_string(sequence.size()));
  }
  return sequence[taken++];
}

}  // namespace

::sarloc::RescuerHandover handover_request(const std::string& responder_id, const std::string& from_node,
                                           TimestampNs stamp) {
  check_id_fits(responder_id, "responder_id");
  check_id_fits(from_node, "from_node");
  ::sarloc::RescuerHandover out;
  out.responder_id(responder_id);
  out.from_node(from_node);
  out.kind(::sarloc::HANDOVER_REQUEST);
  out.stamp(stamp);
  return out;
}

::sarloc::RescuerHandover handover_taken(const std::string& responder_id, const std::string& from_node,
                                         const std::string& to_node, TimestampNs stamp) {
  auto out = handover_request(responder_id, from_node, stamp);
  check_id_fits(to_node, "to_node");
  out.to_node(to_node);
  out.kind(::sarloc::HANDOVER_TAKEN);
  return out;
}

::sarloc::RescuerHandover handover_journal(const estimator::EstimatorJournal& journal, const std::string& from_node,
                                           const std::string& to_node, TimestampNs stamp) {
  if (journal.entries.size() > ::sarloc::HANDOVER_ENTRIES_MAX) {
    throw InputError("rescuer_handover.calls: " + std::to_string(journal.entries.size()) + " entries, at most " +
                     std::to_string(::sarloc::HANDOVER_ENTRIES_MAX) + " (core.handover_journal_entries)");
  }
  check_id_fits(journal.responder_id, "responder_id");
  check_id_fits(from_node, "from_node");
  check_id_fits(to_node, "to_node");
  ::sarloc::RescuerHandover out;
  out.responder_id(journal.responder_id);
  out.from_node(from_node);
  out.to_node(to_node);
  out.kind(journal.overflowed ? ::sarloc::HANDOVER_UNAVAILABLE : ::sarloc::HANDOVER_JOURNAL);
  out.stamp(stamp);
  out.role(static_cast<std::uint8_t>(journal.role));
  if (journal.overflowed) return out;
  for (const auto& entry : journal.entries) {
    out.calls().push_back(static_cast<std::uint8_t>(entry.index()));
    if (const auto* odometry = std::get_if<responder::Odometry>(&entry)) {
      out.odometry_steps().push_back(to_idl(*odometry));
    } else if (const auto* motion = std::get_if<estimator::UnknownMotionCall>(&entry)) {
      ::sarloc::JournalSpan span;
      span.from(motion->from);
      span.until(motion->until);
      out.unknown_motion().push_back(span);
    } else if (const auto* sample = std::get_if<estimator::SensorSample>(&entry)) {
      out.field_measurements().push_back(to_idl(std::get<avalanche::FieldMeasurement>(*sample)));
    } else if (const auto* coast = std::get_if<estimator::CoastCall>(&entry)) {
      out.coasts().push_back(coast->stamp);
    } else if (const auto* done = std::get_if<estimator::MarkDoneCall>(&entry)) {
      out.done_signals().push_back(done->signal_id);
    } else if (const auto* leave = std::get_if<estimator::LeaveToOthersCall>(&entry)) {
      if (leave->signal_ids.size() > ::sarloc::HANDOVER_SIGNALS_MAX) {
        throw InputError("rescuer_handover.leaves.signal_ids: " + std::to_string(leave->signal_ids.size()) +
                         " signals, at most " + std::to_string(::sarloc::HANDOVER_SIGNALS_MAX));
      }
      ::sarloc::JournalLeave out_leave;
      out_leave.signal_ids().assign(leave->signal_ids.begin(), leave->signal_ids.end());
      out_leave.until(leave->until);
      out.leaves().push_back(out_leave);
    } else if (const auto* hint = std::get_if<estimator::PositionHintCall>(&entry)) {
      out.position_hints().push_back(to_idl(hint->own));
    }
  }
  return out;
}

estimator::EstimatorJournal journal_of(const ::sarloc::RescuerHandover& handover) {
  if (handover.kind() != ::sarloc::HANDOVER_JOURNAL) throw InputError("rescuer_handover.kind: not a journal");
  estimator::EstimatorJournal journal;
  journal.responder_id = handover.responder_id().to_string();
  check_identifier(journal.responder_id, "rescuer_handover.responder_id");
  if (handover.role() > static_cast<std::uint8_t>(estimator::ResponderRole::kFirefighter)) {
    throw InputError("rescuer_handover.role = " + std::to_string(handover.role()) + ": not a responder role");
  }
  journal.role = static_cast<estimator::ResponderRole>(handover.role());
  std::size_t odometry = 0, motion = 0, field = 0, coast = 0, done = 0, leave = 0, hint = 0;
  journal.entries.reserve(handover.calls().size());
  const auto own = [&](const std::string& id, const char* field_name) {
    if (id != journal.responder_id) {
      throw InputError(std::string("rescuer_handover.") + field_name + ": an entry of '" + id +
                       "' in the journal of '" + journal.responder_id + "'");
    }
  };
  for (const std::uint8_t call : handover.calls()) {
    switch (call) {
      case ::sarloc::JOURNAL_ODOMETRY: {
        auto o = to_core(next(handover.odometry_steps(), odometry, "odometry_steps"));
        own(o.rescuer_id, "odometry_steps");
        journal.entries.emplace_back(std::move(o));
        break;
      }
      case ::sarloc::JOURNAL_UNKNOWN_MOTION: {
        const auto& span = next(handover.unknown_motion(), motion, "unknown_motion");
        journal.entries.emplace_back(estimator::UnknownMotionCall{span.from(), span.until()});
        break;
      }
      case ::sarloc::JOURNAL_FIELD_MEASUREMENT: {
        auto m = to_core(next(handover.field_measurements(), field, "field_measurements"));
        own(m.rescuer_id, "field_measurements");
        journal.entries.emplace_back(estimator::SensorSample(std::move(m)));
        break;
      }
      case ::sarloc::JOURNAL_COAST:
        journal.entries.emplace_back(estimator::CoastCall{next(handover.coasts(), coast, "coasts")});
        break;
      case ::sarloc::JOURNAL_MARK_DONE:
        journal.entries.emplace_back(estimator::MarkDoneCall{next(handover.done_signals(), done, "done_signals")});
        break;
      case ::sarloc::JOURNAL_LEAVE_TO_OTHERS: {
        const auto& l = next(handover.leaves(), leave, "leaves");
        journal.entries.emplace_back(estimator::LeaveToOthersCall{
            std::set<std::uint32_t>(l.signal_ids().begin(), l.signal_ids().end()), l.until()});
        break;
      }
      case ::sarloc::JOURNAL_POSITION_HINT: {
        auto p = to_core(next(handover.position_hints(), hint, "position_hints"));
        own(p.responder_id, "position_hints");
        journal.entries.emplace_back(estimator::PositionHintCall{std::move(p)});
        break;
      }
      default:
        throw InputError("rescuer_handover.calls: " + std::to_string(call) + " is no journal call");
    }
  }
  if (odometry != handover.odometry_steps().size() || motion != handover.unknown_motion().size() ||
      field != handover.field_measurements().size() || coast != handover.coasts().size() ||
      done != handover.done_signals().size() || leave != handover.leaves().size() ||
      hint != handover.position_hints().size()) {
    throw InputError("rescuer_handover: values that no call names are left over");
  }
  return journal;
}

}  // namespace sarloc::dds
