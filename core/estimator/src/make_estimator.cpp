#include "sarloc/core/estimator/make_estimator.hpp"

#include "sarloc/core/estimator/avalanche_rescuer_estimator.hpp"

namespace sarloc::estimator {

std::unique_ptr<ResponderEstimator> make_estimator(ResponderRole role, const std::string& responder_id,
                                                   const EstimatorConfigs& configs) {
  switch (role) {
    case ResponderRole::kAvalancheRescuer:
      return std::make_unique<AvalancheRescuerEstimator>(responder_id, configs.avalanche_rescuer);
    case ResponderRole::kFirefighter:
      return std::make_unique<FirefighterEstimator>(responder_id, configs.firefighter);
  }
  return nullptr;  // unreachable: every role is handled above
}

}  // namespace sarloc::estimator
