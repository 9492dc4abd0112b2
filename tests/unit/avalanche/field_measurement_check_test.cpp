// The field-sample check every filter makes (validate_field_measurement), through the SOG filter.
#include "sarloc/core/avalanche/sog_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sarloc/core/avalanche/odometry_accumulator.hpp"
#include "sarloc/core/avalanche/simulator.hpp"
#include "sarloc/core/common/chi_square.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"
#include "sog_scenarios.hpp"

namespace sarloc::avalanche {
namespace {

using namespace test;  // sog_scenarios.hpp

TEST(SogFilterTest, RejectsBadMeasurementsNamingTheField) {
  SogConfig cfg;
  cfg.initial_components = 100;
  SogFilter f(cfg);
  FieldMeasurement m;
  m.sequence = 1;
  m.field = Vec3(1e-7, kNaN, 0);
  try {
    f.process(m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field_measurement.field"), std::string::npos);
  }
  m.field = Vec3(100.0, 0, 0);
  EXPECT_THROW(f.process(m), InputError);  // absurd magnitude
  m.field = Vec3::Zero();
  EXPECT_THROW(f.process(m), InputError);  // cannot initialise from zero
  m.field = Vec3(1e-7, 2e-8, -3e-8);
  m.orientation = OrientationObservation{};
  m.orientation->covariance = -Mat3::Identity();
  EXPECT_THROW(f.process(m), InputError);  // non-PD covariance
  m.orientation.reset();
  m.noise_stddev = Vec3(-1, 0, 0);
  EXPECT_THROW(f.process(m), InputError);
  m.noise_stddev = Vec3::Zero();
  f.process(m);
  EXPECT_THROW(f.process(m), InputError);  // same sequence again
  Odometry o;
  o.sequence = 1;
  o.covariance = Mat6::Identity() * 1e-4;
  o.translation = Vec3(kNaN, 0, 0);
  EXPECT_THROW(f.add_odometry(o), InputError);
  o.translation = Vec3(1, 0, 0);
  o.covariance(0, 0) = -1.0;
  EXPECT_THROW(f.add_odometry(o), InputError);
}

}  // namespace
}  // namespace sarloc::avalanche
