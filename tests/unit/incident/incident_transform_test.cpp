#include <gtest/gtest.h>

#include "sarloc/core/incident/incident_transform.hpp"

namespace sarloc::incident {
namespace {

TEST(IncidentTransform, AddsPositionsAndCovariances) {
  GaussianPosition rel;
  rel.position = Vec3(3.0, -2.0, -1.5);
  rel.covariance = Vec3(0.04, 0.09, 0.16).asDiagonal();
  GaussianPosition antenna;
  antenna.position = Vec3(100.0, 50.0, 1.0);
  antenna.covariance << 2.25, 0.3, 0.0, 0.3, 2.25, 0.0, 0.0, 0.0, 6.25;
  const GaussianPosition out = to_incident_frame(rel, antenna);
  EXPECT_TRUE(out.position.isApprox(Vec3(103.0, 48.0, -0.5)));
  EXPECT_TRUE(out.covariance.isApprox(rel.covariance + antenna.covariance));
  EXPECT_TRUE(out.covariance.isApprox(out.covariance.transpose()));
}

}  // namespace
}  // namespace sarloc::incident
