#pragma once
// The configuration of every role's estimator, and the factory that builds a responder's
// estimator from its role.
#include <memory>

#include "sarloc/core/avalanche/rescuer_search.hpp"
#include "sarloc/core/estimator/firefighter_estimator.hpp"
#include "sarloc/core/estimator/responder_estimator.hpp"

namespace sarloc::estimator {

struct EstimatorConfigs {
  avalanche::RescuerSearchConfig avalanche_rescuer;  ///< mission file: sog:, search:, rescuer_search:
  FirefighterEstimatorConfig firefighter;            ///< mission file: building:, firefighter:, rescuers[].entry, .hand

  /// Throws ConfigError naming the key.
  void validate() const {
    avalanche_rescuer.validate();
    firefighter.validate();
  }
};

std::unique_ptr<ResponderEstimator> make_estimator(ResponderRole role, const std::string& responder_id,
                                                   const EstimatorConfigs& configs);

}  // namespace sarloc::estimator
