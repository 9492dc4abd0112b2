// The avalanche rescuer's estimator behind the generic interface: what goes in and out.
#include "sarloc/core/estimator/avalanche_rescuer_estimator.hpp"

#include <gtest/gtest.h>

#include "sarloc/core/avalanche/dipole_model.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/estimator/make_estimator.hpp"

namespace sarloc::estimator {
namespace {

avalanche::FieldMeasurement field_from(const Vec3& transmitter, const std::string& rescuer, std::uint64_t sequence) {
  avalanche::FieldMeasurement m;
  m.rescuer_id = rescuer;
  m.signal_id = 3;
  m.sequence = sequence;
  m.stamp = static_cast<TimestampNs>(sequence) * 1'000'000'000;
  m.field = avalanche::DipoleField::field(-transmitter, Vec3(0.01, 0.0, 0.002));  // receiver at the origin
  m.noise_stddev = Vec3::Constant(1e-9);
  return m;
}

EstimatorConfigs small_configs() {
  EstimatorConfigs c;
  c.avalanche_rescuer.sog.initial_components = 200;
  return c;
}

TEST(AvalancheRescuerEstimator, FieldSampleGivesAnEstimateAndGuidanceForThatSignal) {
  auto est = make_estimator(ResponderRole::kAvalancheRescuer, "r1", small_configs());
  ASSERT_EQ(est->role(), ResponderRole::kAvalancheRescuer);
  EXPECT_EQ(est->responder_id(), "r1");
  const auto outcome = est->process(field_from(Vec3(12.0, 3.0, -2.0), "r1", 1));
  const auto* out = std::get_if<EstimatorOutput>(&outcome);
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(out->estimates.size(), 1U);
  EXPECT_EQ(out->estimates[0].signal_id, 3U);
  EXPECT_EQ(out->estimates[0].rescuer_id, "r1");
  ASSERT_TRUE(out->guidance.has_value());
  EXPECT_EQ(out->guidance->signal_id, 3U);
  EXPECT_FALSE(out->position.has_value()) << "an avalanche rescuer's position comes from GNSS, not the daemon";
  ASSERT_TRUE(est->estimate_of(3).has_value());
  EXPECT_FALSE(est->estimate_of(4).has_value());
  EXPECT_EQ(est->active_filters(), 1U);
}

TEST(AvalancheRescuerEstimator, RefusalsLeaveItUntouched) {
  auto est = make_estimator(ResponderRole::kAvalancheRescuer, "r1", small_configs());
  const auto outcome = est->process(field_from(Vec3(12.0, 3.0, -2.0), "someone-else", 1));
  const auto* rejected = std::get_if<responder::Rejection>(&outcome);
  ASSERT_NE(rejected, nullptr);
  EXPECT_EQ(rejected->reason, responder::RejectReason::kWrongRescuer);
  EXPECT_EQ(est->active_filters(), 0U);

  responder::Odometry o;
  o.rescuer_id = "r1";
  o.sequence = 1;
  o.interval_end = 1;
  o.translation = Vec3(1e3, 0.0, 0.0);  // an absurd step
  const auto refused = est->add_odometry(o);
  ASSERT_TRUE(std::holds_alternative<responder::Rejection>(refused));
  EXPECT_EQ(std::get<responder::Rejection>(refused).reason, responder::RejectReason::kAbsurdMotion);
}

TEST(ResponderRole, NamesRoundTripAndUnknownNamesAreRefusedWithTheKey) {
  EXPECT_EQ(parse_responder_role(to_string(ResponderRole::kAvalancheRescuer), "k"), ResponderRole::kAvalancheRescuer);
  try {
    parse_responder_role("ninja", "rescuers[2].role");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("rescuers[2].role = 'ninja'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace sarloc::estimator
