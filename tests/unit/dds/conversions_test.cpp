// to_core(to_idl(x)) == x for every message, field by field; plus the wire rules.
#include "sarloc/dds/conversions.hpp"
#include "sarloc/idl/incidentPubSubTypes.h"

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/identifier.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "support/sample_messages.hpp"

namespace sarloc::dds {
namespace {

void expect_same(const GaussianPosition& a, const GaussianPosition& b) {
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.covariance, b.covariance);
}

TEST(Conversions, FieldMeasurementRoundTrips) {
  const auto in = test::sample_field_measurement();
  const auto out = to_core(to_idl(in));
  EXPECT_EQ(out.rescuer_id, in.rescuer_id);
  EXPECT_EQ(out.signal_id, in.signal_id);
  EXPECT_EQ(out.sequence, in.sequence);
  EXPECT_EQ(out.stamp, in.stamp);
  EXPECT_EQ(out.field, in.field);
  EXPECT_EQ(out.noise_stddev, in.noise_stddev);
  EXPECT_EQ(out.valid_axes, in.valid_axes);
  EXPECT_EQ(out.event, in.event);
  EXPECT_EQ(out.unattributed_pulses, in.unattributed_pulses);
  EXPECT_EQ(out.transmitter.carrier_offset_hz, in.transmitter.carrier_offset_hz);
  EXPECT_EQ(out.transmitter.carrier_sigma_hz, in.transmitter.carrier_sigma_hz);
  EXPECT_EQ(out.transmitter.period_s, in.transmitter.period_s);
  EXPECT_EQ(out.transmitter.period_sigma_s, in.transmitter.period_sigma_s);
  ASSERT_TRUE(out.orientation.has_value());
  EXPECT_EQ(out.orientation->rpy, in.orientation->rpy);
  EXPECT_EQ(out.orientation->covariance, in.orientation->covariance);
}

TEST(Conversions, FieldMeasurementWithoutOrientationStaysWithout) {
  auto in = test::sample_field_measurement();
  in.orientation.reset();
  EXPECT_FALSE(to_idl(in).has_orientation());
  EXPECT_FALSE(to_core(to_idl(in)).orientation.has_value());
}

TEST(Conversions, CovarianceIsRowMajorOnTheWire) {
  const auto in = test::sample_odometry();
  const auto wire = to_idl(in);
  EXPECT_EQ(wire.covariance()[1], in.covariance(0, 1));
  EXPECT_EQ(wire.covariance()[6], in.covariance(1, 0));
  EXPECT_EQ(wire.covariance()[35], in.covariance(5, 5));
}

TEST(Conversions, OdometryRoundTrips) {
  const auto in = test::sample_odometry();
  const auto out = to_core(to_idl(in));
  EXPECT_EQ(out.rescuer_id, in.rescuer_id);
  EXPECT_EQ(out.sequence, in.sequence);
  EXPECT_EQ(out.interval_start, in.interval_start);
  EXPECT_EQ(out.interval_end, in.interval_end);
  EXPECT_EQ(out.translation, in.translation);
  EXPECT_EQ(out.rotation_rpy, in.rotation_rpy);
  EXPECT_EQ(out.covariance, in.covariance);
  EXPECT_EQ(out.source, in.source);
}

TEST(Conversions, VictimEstimateRoundTrips) {
  const auto in = test::sample_victim_estimate();
  const auto wire = to_idl(in, 99);
  EXPECT_EQ(wire.measurement_sequence(), 99U);
  const auto out = to_core(wire);
  EXPECT_EQ(out.rescuer_id, in.rescuer_id);
  EXPECT_EQ(out.signal_id, in.signal_id);
  EXPECT_EQ(out.stamp, in.stamp);
  EXPECT_EQ(out.status, in.status);
  expect_same(out.relative, in.relative);
  ASSERT_EQ(out.top_components.size(), in.top_components.size());
  for (std::size_t i = 0; i < in.top_components.size(); ++i) {
    EXPECT_EQ(out.top_components[i].weight, in.top_components[i].weight);
    EXPECT_EQ(out.top_components[i].mean, in.top_components[i].mean);
    EXPECT_EQ(out.top_components[i].covariance, in.top_components[i].covariance);
  }
  EXPECT_EQ(out.live_components, in.live_components);
  EXPECT_EQ(out.moment, in.moment);
  EXPECT_EQ(out.signal_event, in.signal_event);
  EXPECT_EQ(out.signal_event_stamp, in.signal_event_stamp);
  EXPECT_EQ(out.repeat, in.repeat);
  EXPECT_EQ(out.repeat_of_signal, in.repeat_of_signal);
  EXPECT_EQ(out.transmitter.carrier_offset_hz, in.transmitter.carrier_offset_hz);
  EXPECT_EQ(out.transmitter.carrier_sigma_hz, in.transmitter.carrier_sigma_hz);
  EXPECT_EQ(out.transmitter.period_s, in.transmitter.period_s);
  EXPECT_EQ(out.transmitter.period_sigma_s, in.transmitter.period_sigma_s);
}

// A signature no receiver can have measured is refused by name: incident command would
// otherwise compare it with every other rescuer's.
TEST(Conversions, ATransmitterSignatureOutOfRangeIsRefusedByName) {
  const std::vector<std::pair<std::function<void(::sarloc::TransmitterSignature&)>, std::string>> bad{
      {[](auto& s) { s.carrier_offset_hz(std::nan("")); }, "victim_estimate.transmitter.carrier_offset_hz = nan"},
      {[](auto& s) { s.carrier_sigma_hz(-1.0); }, "victim_estimate.transmitter.carrier_sigma_hz = -1"},
      {[](auto& s) { s.period_s(40.0); }, "victim_estimate.transmitter.period_s = 40"},
      {[](auto& s) { s.period_sigma_s(std::numeric_limits<double>::infinity()); },
       "victim_estimate.transmitter.period_sigma_s = inf"}};
  for (const auto& [spoil, message] : bad) {
    auto wire = to_idl(test::sample_victim_estimate());
    spoil(wire.transmitter());
    try {
      (void)to_core(wire);
      ADD_FAILURE() << "expected InputError: " << message;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  auto wire = to_idl(test::sample_field_measurement());
  wire.transmitter().carrier_offset_hz(5000.0);
  EXPECT_THROW((void)to_core(wire), InputError);
}

// A repeat names another signal of the same receiver, and a state the wire knows.
TEST(Conversions, AVictimEstimateRepeatingItselfOrOfAnUnknownStateIsRefusedByName) {
  auto in = test::sample_victim_estimate();
  in.repeat_of_signal = in.signal_id;
  try {
    (void)to_core(to_idl(in));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("victim_estimate.repeat_of_signal = 3"), std::string::npos) << e.what();
  }
  auto wire = to_idl(test::sample_victim_estimate());
  wire.repeat(static_cast<::sarloc::RepeatState>(5));
  try {
    (void)to_core(wire);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("victim_estimate.repeat = 5"), std::string::npos) << e.what();
  }
}

// A device's estimate carries its own fix of the estimate's epoch (incident command places it
// with that); one naming another responder is refused.
TEST(Conversions, VictimEstimateCarriesTheReportersFix) {
  auto in = test::sample_victim_estimate();
  EXPECT_FALSE(to_core(to_idl(in)).reporter.has_value());
  responder::ResponderPosition fix;
  fix.responder_id = in.rescuer_id;
  fix.team_id = "north";
  fix.stamp = in.stamp - 7;
  fix.position.position = Vec3(1.0, 2.0, 3.0);
  fix.floor = 2;
  fix.source = responder::PositionSource::kMapAided;
  in.reporter = fix;
  const auto out = to_core(to_idl(in));
  ASSERT_TRUE(out.reporter.has_value());
  EXPECT_EQ(out.reporter->stamp, fix.stamp);
  EXPECT_EQ(out.reporter->position.position, fix.position.position);
  EXPECT_EQ(out.reporter->floor, 2);
  EXPECT_EQ(out.reporter->source, responder::PositionSource::kMapAided);
  in.reporter->responder_id = "someone-else";
  EXPECT_THROW(to_core(to_idl(in)), InputError);
}

TEST(Conversions, VictimEstimateKeepsOnlyTheBoundedNumberOfComponents) {
  auto in = test::sample_victim_estimate();
  in.top_components.resize(::sarloc::MIXTURE_SUMMARY_MAX + 5, in.top_components.front());
  EXPECT_EQ(to_idl(in).top_components().size(), ::sarloc::MIXTURE_SUMMARY_MAX);
}

TEST(Conversions, GuidanceRoundTrips) {
  const auto in = test::sample_guidance();
  const auto out = to_core(to_idl(in, 5));
  EXPECT_EQ(out.rescuer_id, in.rescuer_id);
  EXPECT_EQ(out.signal_id, in.signal_id);
  EXPECT_EQ(out.stamp, in.stamp);
  EXPECT_EQ(out.mode, in.mode);
  EXPECT_EQ(out.bearing_rad, in.bearing_rad);
  EXPECT_EQ(out.heading_rad, in.heading_rad);
  EXPECT_EQ(out.distance_m, in.distance_m);
  EXPECT_EQ(out.step_m, in.step_m);
  EXPECT_EQ(out.uncertainty_radius_m, in.uncertainty_radius_m);
}

TEST(Conversions, ResponderPositionRoundTrips) {
  const auto in = test::sample_responder_position();
  const auto out = to_core(to_idl(in));
  EXPECT_EQ(out.responder_id, in.responder_id);
  EXPECT_EQ(out.team_id, in.team_id);
  EXPECT_EQ(out.stamp, in.stamp);
  expect_same(out.position, in.position);
  EXPECT_EQ(out.heading_rad, in.heading_rad);
  EXPECT_EQ(out.floor, in.floor);
  EXPECT_EQ(out.source, in.source);
  EXPECT_EQ(out.converged, in.converged);
  EXPECT_EQ(out.map_error_suspected, in.map_error_suspected);
  EXPECT_EQ(out.confirmed, in.confirmed);
  EXPECT_EQ(out.ambiguous, in.ambiguous);
}

TEST(Conversions, ResponderCandidatesRoundTripAndImpossibleOnesAreRefusedByField) {
  const auto in = test::sample_responder_candidates();
  const auto out = to_core(to_idl(in));
  EXPECT_EQ(out.responder_id, in.responder_id);
  EXPECT_EQ(out.stamp, in.stamp);
  ASSERT_EQ(out.candidates.size(), in.candidates.size());
  for (std::size_t i = 0; i < in.candidates.size(); ++i) {
    expect_same(out.candidates[i].position, in.candidates[i].position);
    EXPECT_EQ(out.candidates[i].floor, in.candidates[i].floor);
    EXPECT_EQ(out.candidates[i].weight, in.candidates[i].weight);
  }
  EXPECT_TRUE(to_core(to_idl(responder::ResponderCandidates{"ff1", 5, {}})).candidates.empty())
      << "the end of an ambiguity";

  const auto refusal = [](const std::function<void(::sarloc::ResponderCandidates&)>& spoil) {
    auto wire = to_idl(test::sample_responder_candidates());
    spoil(wire);
    try {
      (void)to_core(wire);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal([](auto& w) { w.candidates()[1].weight(0.0); }),
            "responder_candidates.candidates.weight = 0.000000: must be in (0, 1]");
  EXPECT_EQ(refusal([](auto& w) { w.candidates()[0].weight(std::nan("")); }),
            "responder_candidates.candidates.weight = nan: must be in (0, 1]");
  EXPECT_EQ(refusal([](auto& w) { w.candidates()[0].weight(0.9); }),
            "responder_candidates.candidates.weight: they sum to 1.150000, more than 1");
  EXPECT_EQ(refusal([](auto& w) { w.candidates()[0].position().position().x(INFINITY); }),
            "responder_candidates.candidates.position: non-finite value");
  EXPECT_EQ(refusal([](auto& w) { w.candidates()[1].position().covariance()[4] = std::nan(""); }),
            "responder_candidates.candidates.position: non-finite value");
  responder::ResponderCandidates five = test::sample_responder_candidates();
  five.candidates.resize(5, five.candidates[1]);
  for (auto& c : five.candidates) c.weight = 0.1;
  try {
    (void)to_idl(five);
    FAIL() << "five places are more than the topic holds";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "responder_candidates.candidates: 5 places, at most 4");
  }
}

TEST(Conversions, FusedVictimRoundTrips) {
  const auto in = test::sample_fused_victim();
  const auto out = to_core(to_idl(in));
  EXPECT_EQ(out.victim_id, in.victim_id);
  expect_same(out.position, in.position);
  ASSERT_EQ(out.sources.size(), in.sources.size());
  for (std::size_t i = 0; i < in.sources.size(); ++i) {
    EXPECT_EQ(out.sources[i].rescuer_id, in.sources[i].rescuer_id);
    EXPECT_EQ(out.sources[i].signal_id, in.sources[i].signal_id);
    EXPECT_EQ(out.sources[i].last_update, in.sources[i].last_update);
    EXPECT_EQ(out.sources[i].signal_event, in.sources[i].signal_event);
    EXPECT_EQ(out.sources[i].signal_event_stamp, in.sources[i].signal_event_stamp);
  }
  EXPECT_EQ(out.state, in.state);
  EXPECT_EQ(out.first_seen, in.first_seen);
  EXPECT_EQ(out.last_update, in.last_update);
  EXPECT_EQ(out.located_at, in.located_at);
  EXPECT_EQ(out.found_at, in.found_at);
  EXPECT_EQ(out.evidence_conflict, in.evidence_conflict);
  EXPECT_EQ(out.possibly_same_as, in.possibly_same_as);
}

TEST(Conversions, TeamStatusRoundTrips) {
  const auto in = test::sample_team_status();
  const auto out = to_core(to_idl(in));
  EXPECT_EQ(out.team_id, in.team_id);
  EXPECT_EQ(out.stamp, in.stamp);
  ASSERT_EQ(out.members.size(), in.members.size());
  for (std::size_t i = 0; i < in.members.size(); ++i) {
    EXPECT_EQ(out.members[i].responder_id, in.members[i].responder_id);
    expect_same(out.members[i].last_position, in.members[i].last_position);
    EXPECT_EQ(out.members[i].last_seen, in.members[i].last_seen);
    EXPECT_EQ(out.members[i].link, in.members[i].link);
    EXPECT_EQ(out.members[i].accountability, in.members[i].accountability);
  }
}

// A signed-off member crosses the wire as LINK_LOST + ACCOUNTED + RESPONDER_FLAG_SIGNED_OFF (no
// new enumerator for @final readers) and comes back signed off; a lost one stays lost.
TEST(Conversions, ASignedOffMemberIsLostAndAccountedOnTheWireWithItsFlag) {
  auto in = test::sample_team_status();
  ASSERT_GE(in.members.size(), 2U);
  in.members[0].link = incident::LinkState::kSignedOff;
  in.members[0].accountability = incident::AccountabilityState::kAccounted;
  in.members[1].link = incident::LinkState::kLost;
  const auto wire = to_idl(in);
  EXPECT_EQ(wire.members()[0].link(), ::sarloc::LINK_LOST);
  EXPECT_EQ(wire.members()[0].accountability(), ::sarloc::ACCOUNTABILITY_ACCOUNTED);
  EXPECT_NE(wire.members()[0].flags() & ::sarloc::RESPONDER_FLAG_SIGNED_OFF, 0U);
  EXPECT_EQ(wire.members()[1].flags() & ::sarloc::RESPONDER_FLAG_SIGNED_OFF, 0U);
  const auto out = to_core(wire);
  EXPECT_EQ(out.members[0].link, incident::LinkState::kSignedOff);
  EXPECT_EQ(out.members[1].link, incident::LinkState::kLost);
}

// The search plan: every strip with its outline, ends, coverage, rescuer and next point; the
// IDL's bounds and a NaN from the wire refused by name.
TEST(Conversions, SearchPlanRoundTrips) {
  auto p = test::sample_search_plan();
  const auto back = to_core(to_idl(p));
  EXPECT_EQ(back.incident_id, p.incident_id);
  EXPECT_EQ(back.stamp, p.stamp);
  EXPECT_EQ(back.deposit, p.deposit);
  EXPECT_EQ(back.plan.revision, p.plan.revision);
  EXPECT_DOUBLE_EQ(back.plan.searched, p.plan.searched);
  ASSERT_EQ(back.plan.strips.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.plan.strips[i].strip.index, p.plan.strips[i].strip.index);
    EXPECT_EQ(back.plan.strips[i].strip.outline, p.plan.strips[i].strip.outline);
    EXPECT_EQ(back.plan.strips[i].strip.top, p.plan.strips[i].strip.top);
    EXPECT_EQ(back.plan.strips[i].strip.bottom, p.plan.strips[i].strip.bottom);
    EXPECT_EQ(back.plan.strips[i].strip.width_m, p.plan.strips[i].strip.width_m);
    EXPECT_EQ(back.plan.strips[i].searched, p.plan.strips[i].searched);
    EXPECT_EQ(back.plan.strips[i].done, p.plan.strips[i].done);
    EXPECT_EQ(back.plan.strips[i].rescuer_id, p.plan.strips[i].rescuer_id);
    EXPECT_EQ(back.next_points[i], p.next_points[i]);
    EXPECT_EQ(back.plan.strips[i].helper_id, p.plan.strips[i].helper_id);
    EXPECT_EQ(back.helper_next_points[i], p.helper_next_points[i]);
  }
  ASSERT_EQ(back.handed_over.size(), 2u);
  EXPECT_EQ(back.handed_over[0].rescuer_id, "r2");
  EXPECT_EQ(back.handed_over[0].signal_id, 3u);
  EXPECT_EQ(back.handed_over[0].victim_id, 7u);
  EXPECT_EQ(back.handed_over[0].pursued_by, "r1");
  EXPECT_EQ(back.handed_over[1].victim_id, 0u) << "a transmitter not yet placed";
  EXPECT_EQ(back.handed_over[1].pursued_by, "r3");
  ASSERT_EQ(back.digs.digs.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.digs.digs[i].victim_id, p.digs.digs[i].victim_id);
    EXPECT_EQ(back.digs.digs[i].depth_m, p.digs.digs[i].depth_m);
    EXPECT_EQ(back.digs.digs[i].buried_min, p.digs.digs[i].buried_min);
    EXPECT_EQ(back.digs.digs[i].start_min, p.digs.digs[i].start_min);
    EXPECT_EQ(back.digs.digs[i].done_min, p.digs.digs[i].done_min);
    EXPECT_EQ(back.digs.digs[i].survival, p.digs.digs[i].survival);
    EXPECT_EQ(back.digs.digs[i].digger_id, p.digs.digs[i].digger_id);
  }
  EXPECT_EQ(back.digs.expected_survivors, p.digs.expected_survivors);
  EXPECT_EQ(back.incident_start, p.incident_start);
  auto wire = to_idl(p);
  wire.digs()[1].survival(std::nan(""));
  try {
    to_core(wire);
    ADD_FAILURE() << "a NaN survival accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("search_plan.digs.survival"), std::string::npos) << e.what();
  }
  wire = to_idl(p);
  wire.digs()[0].depth_m(-1.0);
  EXPECT_THROW(to_core(wire), InputError) << "a negative depth";
  wire = to_idl(p);
  wire.strips()[0].next_point().x(std::nan(""));
  try {
    to_core(wire);
    ADD_FAILURE() << "a NaN next point accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("search_plan.strips.next_point"), std::string::npos) << e.what();
  }
  wire = to_idl(p);
  wire.searched_fraction(1.5);
  EXPECT_THROW(to_core(wire), InputError);
  p.deposit.assign(::sarloc::OUTLINE_POINTS_MAX + 1, incident::Vec2(1, 1));
  EXPECT_THROW(to_idl(p), InputError) << "beyond the IDL's bound";
}

TEST(Conversions, IdentifierLongerThanTheBoundIsRefusedByName) {
  auto in = test::sample_field_measurement();
  in.rescuer_id = std::string(::sarloc::ID_MAX + 1, 'x');
  try {
    (void)to_idl(in);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field_measurement.rescuer_id"), std::string::npos) << e.what();
  }
  in.rescuer_id = std::string(::sarloc::ID_MAX, 'x');  // exactly the bound is fine
  EXPECT_EQ(to_core(to_idl(in)).rescuer_id, in.rescuer_id);
}

TEST(Conversions, UnknownSignalEventFromTheWireIsRefusedByName) {
  auto wire = to_idl(test::sample_field_measurement());
  wire.signal_event(static_cast<::sarloc::SignalEvent>(9));
  try {
    (void)to_core(wire);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field_measurement.signal_event = 9"), std::string::npos) << e.what();
  }
}

TEST(Conversions, UnknownEnumValueFromTheWireIsRefusedByName) {
  auto wire = to_idl(test::sample_guidance());
  wire.mode(static_cast<::sarloc::GuidanceMode>(17));
  try {
    (void)to_core(wire);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("guidance.mode = 17"), std::string::npos) << e.what();
  }
}

// A disposal carries only the instance handle: the victim id comes back from it, and a
// handle that is not a FusedVictim's gives nothing.
TEST(Conversions, VictimIdOfAFusedVictimInstanceHandle) {
  for (const std::uint32_t id : {1U, 7U, 256U, 70000U, 4294967295U}) {
    ::sarloc::FusedVictim v;
    v.victim_id(id);
    ::sarloc::FusedVictimPubSubType type;
    eprosima::fastrtps::rtps::InstanceHandle_t handle;
    ASSERT_TRUE(type.getKey(&v, &handle));
    EXPECT_EQ(victim_id_of(handle), id);
  }
  eprosima::fastrtps::rtps::InstanceHandle_t other;
  other.value[0] = 0;
  other.value[3] = 5;
  other.value[9] = 1;  // not a 4-byte key
  EXPECT_FALSE(victim_id_of(other).has_value());
}

// Every id from the wire passes the one identifier rule, or the sample is refused naming the
// field (issue 59: a responder_id "bad\xff\xfeid" reached the dashboard and ended it).
TEST(Conversions, AnIdThatIsNotAnIdentifierIsRefusedByName) {
  auto wire = to_idl(test::sample_responder_position());
  wire.responder_id("bad\xff\xfeid");
  try {
    (void)to_core(wire);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "responder_position.responder_id = 'bad\\xFF\\xFEid': not an identifier (1-64 of A-Z a-z 0-9 _ . -)");
  }
  auto alarm = to_idl(test::sample_incident_alarm());
  alarm.acknowledged_by("<img src=x onerror=alert(1)>");
  EXPECT_THROW((void)to_core(alarm), InputError);
  alarm.acknowledged_by("");
  EXPECT_NO_THROW((void)to_core(alarm)) << "nobody has acknowledged it yet";
}

// Random bytes in every id field of every type: each sample either converts with ids that are
// identifiers, or is refused with an InputError naming that field. Seeded: 600 cases per field.
TEST(Conversions, RandomBytesInEveryIdFieldNeverPassAndNeverCrash) {
  std::mt19937 rng(59);
  auto random_id = [&rng]() {
    std::uniform_int_distribution<int> length(0, 64);
    std::uniform_int_distribution<int> byte(0, 255);
    std::bernoulli_distribution mostly_plain(0.5);
    std::string id(static_cast<std::size_t>(length(rng)), 'a');
    for (auto& c : id) c = mostly_plain(rng) ? static_cast<char>('a' + byte(rng) % 26) : static_cast<char>(byte(rng));
    return id;
  };
  struct Field {
    std::string name;
    std::function<std::vector<std::string>(const std::string&)> convert;  // the ids to_core returned
  };
  const std::vector<Field> fields{
      {"field_measurement.rescuer_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_field_measurement());
         w.rescuer_id(id);
         return std::vector<std::string>{to_core(w).rescuer_id};
       }},
      {"odometry.rescuer_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_odometry());
         w.rescuer_id(id);
         return std::vector<std::string>{to_core(w).rescuer_id};
       }},
      {"victim_estimate.rescuer_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_victim_estimate());
         w.rescuer_id(id);
         return std::vector<std::string>{to_core(w).rescuer_id};
       }},
      {"guidance.rescuer_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_guidance());
         w.rescuer_id(id);
         return std::vector<std::string>{to_core(w).rescuer_id};
       }},
      {"responder_position.responder_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_responder_position());
         w.responder_id(id);
         return std::vector<std::string>{to_core(w).responder_id};
       }},
      {"responder_position.team_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_responder_position());
         w.team_id(id);
         const auto c = to_core(w);
         return std::vector<std::string>{c.responder_id, c.team_id};
       }},
      {"responder_candidates.responder_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_responder_candidates());
         w.responder_id(id);
         return std::vector<std::string>{to_core(w).responder_id};
       }},
      {"fused_victim.sources.rescuer_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_fused_victim());
         w.sources()[0].rescuer_id(id);
         return std::vector<std::string>{to_core(w).sources[0].rescuer_id};
       }},
      {"team_status.team_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_team_status());
         w.team_id(id);
         return std::vector<std::string>{to_core(w).team_id};
       }},
      {"team_status.members.responder_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_team_status());
         w.members()[0].responder_id(id);
         return std::vector<std::string>{to_core(w).members[0].responder_id};
       }},
      {"responder_alarm.responder_id",
       [](const std::string& id) {
         auto w = to_idl(test::sample_responder_alarm());
         w.responder_id(id);
         return std::vector<std::string>{to_core(w).responder_id};
       }},
      {"incident_alarm.acknowledged_by",
       [](const std::string& id) {
         auto w = to_idl(test::sample_incident_alarm());
         w.acknowledged_by(id);
         const auto c = to_core(w);
         return std::vector<std::string>{c.alarm.responder_id, c.acknowledged_by};
       }},
  };
  // Optional (may be empty): a responder's team, the team of responders without one, who acknowledged.
  const bool optional[] = {false, false, false, false, false, true, false, false, true, false, false, true};
  for (std::size_t f = 0; f < fields.size(); ++f) {
    int refused = 0;
    for (int k = 0; k < 600; ++k) {
      const std::string id = random_id();
      try {
        for (const auto& out : fields[f].convert(id)) {
          EXPECT_TRUE(is_identifier(out) || (optional[f] && out.empty())) << fields[f].name << " let " << printable_excerpt(out) << " through";
        }
      } catch (const InputError& e) {
        ++refused;
        EXPECT_EQ(std::string(e.what()).rfind(fields[f].name + " = ", 0), 0U) << e.what();
        EXPECT_FALSE(is_identifier(id)) << fields[f].name << " refused a good id " << id;
      }
    }
    EXPECT_GT(refused, 100) << fields[f].name << ": the random ids were mostly not identifiers";
  }
}

}  // namespace
}  // namespace sarloc::dds
