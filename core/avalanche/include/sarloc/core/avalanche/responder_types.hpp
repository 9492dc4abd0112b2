#pragma once
// The responder vocabulary (core/responder) that the avalanche search consumes and produces,
// named inside sarloc::avalanche so its code reads as before.
#include "sarloc/core/responder/guidance.hpp"
#include "sarloc/core/responder/odometry.hpp"
#include "sarloc/core/responder/rejection.hpp"
#include "sarloc/core/responder/victim_estimate.hpp"

namespace sarloc::avalanche {

using responder::EstimatorStatus;
using responder::Guidance;
using responder::GuidanceMode;
using responder::MixtureComponentSummary;
using responder::Odometry;
using responder::OdometrySource;
using responder::Rejection;
using responder::RejectReason;
using responder::VictimEstimate;

}  // namespace sarloc::avalanche
