#pragma once
// The one place where IDL types (sarloc::X, generated) and core types (sarloc::avalanche::X,
// sarloc::incident::X) meet. Every pair round-trips exactly (tests/unit/dds/conversions_test).
//
// to_core() rejects what the wire can carry but the core cannot mean: enum values out of range
// (a peer built from a newer IDL) throw sarloc::InputError naming the field and value.
// to_idl() rejects what the wire cannot carry: identifiers longer than sarloc::ID_MAX.
// Finite-ness and plausibility of numbers are the core's input validation, not this layer's.
#include <fastdds/rtps/common/InstanceHandle.h>

#include <optional>

#include "sarloc/core/avalanche/field_measurement.hpp"
#include "sarloc/core/incident/alarm_board.hpp"
#include "sarloc/core/incident/fused_victim.hpp"
#include "sarloc/core/incident/incident_frame.hpp"
#include "sarloc/core/incident/search_plan.hpp"
#include "sarloc/core/incident/team_status.hpp"
#include "sarloc/core/responder/alarm.hpp"
#include "sarloc/core/responder/guidance.hpp"
#include "sarloc/core/responder/odometry.hpp"
#include "sarloc/core/responder/responder_candidates.hpp"
#include "sarloc/core/responder/responder_position.hpp"
#include "sarloc/core/responder/victim_estimate.hpp"
#include "sarloc/idl/avalanche.h"
#include "sarloc/idl/common.h"
#include "sarloc/idl/incident.h"
#include "sarloc/idl/responder.h"

namespace sarloc::dds {

/// An id from the wire, fit for a log line or a warning whatever its bytes: itself when it is an
/// identifier (sarloc/core/common/identifier.hpp), else its printable excerpt.
std::string printable_id(const eprosima::fastrtps::fixed_string<::sarloc::ID_MAX>& id);

// Common value types.
::sarloc::Vector3 to_idl(const Vec3& v);
Vec3 to_core(const ::sarloc::Vector3& v);
::sarloc::Quaternion to_idl(const Quat& q);
Quat to_core(const ::sarloc::Quaternion& q);
::sarloc::PositionWithCovariance to_idl(const GaussianPosition& p);
GaussianPosition to_core(const ::sarloc::PositionWithCovariance& p);
::sarloc::PoseWithCovariance to_idl(const GaussianPose& p);
GaussianPose to_core(const ::sarloc::PoseWithCovariance& p);

// Avalanche search.
::sarloc::TransmitterSignature to_idl(const responder::TransmitterSignature& s);
/// Throws InputError naming `where`.<field> (responder::check_signature).
responder::TransmitterSignature to_core(const ::sarloc::TransmitterSignature& s, const std::string& where);
::sarloc::FieldMeasurement to_idl(const avalanche::FieldMeasurement& m);
avalanche::FieldMeasurement to_core(const ::sarloc::FieldMeasurement& m);
::sarloc::Odometry to_idl(const responder::Odometry& o);
responder::Odometry to_core(const ::sarloc::Odometry& o);
::sarloc::VictimEstimate to_idl(const responder::VictimEstimate& e, std::uint64_t measurement_sequence = 0);
responder::VictimEstimate to_core(const ::sarloc::VictimEstimate& e);
::sarloc::Guidance to_idl(const responder::Guidance& g, std::uint64_t measurement_sequence = 0);
responder::Guidance to_core(const ::sarloc::Guidance& g);

// Incident picture.
::sarloc::ResponderPosition to_idl(const responder::ResponderPosition& r);
responder::ResponderPosition to_core(const ::sarloc::ResponderPosition& r);
/// Throws InputError naming the field: more than POSITION_CANDIDATES_MAX places, a non-finite
/// place, a weight outside (0, 1] or weights that sum to more than 1.
::sarloc::ResponderCandidates to_idl(const responder::ResponderCandidates& c);
responder::ResponderCandidates to_core(const ::sarloc::ResponderCandidates& c);
::sarloc::FusedVictim to_idl(const incident::FusedVictim& v);
incident::FusedVictim to_core(const ::sarloc::FusedVictim& v);
::sarloc::TeamStatus to_idl(const incident::TeamStatus& t);
incident::TeamStatus to_core(const ::sarloc::TeamStatus& t);
::sarloc::ResponderAlarm to_idl(const responder::ResponderAlarm& a);
responder::ResponderAlarm to_core(const ::sarloc::ResponderAlarm& a);
::sarloc::IncidentAlarm to_idl(const incident::IncidentAlarm& a);
incident::IncidentAlarm to_core(const ::sarloc::IncidentAlarm& a);
/// The name is cut to TEXT_MAX characters (a display name).
::sarloc::IncidentFrame to_idl(const incident::IncidentFrame& f);
incident::IncidentFrame to_core(const ::sarloc::IncidentFrame& f);
/// InputError when the plan exceeds the IDL's bounds (OUTLINE_POINTS_MAX, SEARCH_STRIPS_MAX).
::sarloc::SearchPlan to_idl(const incident::SearchPlanPicture& p);
/// InputError naming the field for a non-finite point or fraction, a bad rescuer id.
incident::SearchPlanPicture to_core(const ::sarloc::SearchPlan& p);
/// The victim_id of a FusedVictim instance (a disposal carries only its instance handle):
/// the key's serialised form, checked by computing the handle of that id again; nothing if
/// the handle is not a FusedVictim's.
std::optional<std::uint32_t> victim_id_of(const eprosima::fastrtps::rtps::InstanceHandle_t& instance);
/// The alarm_id of an IncidentAlarm instance, the same way.
std::optional<std::uint32_t> alarm_id_of(const eprosima::fastrtps::rtps::InstanceHandle_t& instance);

}  // namespace sarloc::dds
