#pragma once
// What a filter tells the world about one transmitter: a reduced mixture, not the full belief.
#include <optional>
#include <string>
#include <vector>

#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

enum class EstimatorStatus : std::uint8_t {
  kInitialising = 0,  ///< no measurement yet
  kMultimodal = 1,    ///< several hypotheses alive
  kConverged = 2,     ///< one dominant mode
  kLocated = 3,       ///< uncertainty small enough to walk onto it (docs/estimation/avalanche.md)
  kFound = 4,         ///< rescuer stands over the estimate: probe here
};

struct MixtureComponentSummary {
  double weight = 0.0;
  Vec3 mean = Vec3::Zero();            ///< rescuer-relative frame G_k (m)
  Mat3 covariance = Mat3::Identity();  ///< m^2
};

struct VictimEstimate {
  std::string rescuer_id;
  std::uint32_t signal_id = 0;
  TimestampNs stamp = 0;
  EstimatorStatus status = EstimatorStatus::kInitialising;
  GaussianPosition relative;              ///< victim in G_k (rescuer-centred, ENU-aligned)
  std::optional<GaussianPosition> incident;  ///< victim in the incident frame, if pose known
  std::vector<MixtureComponentSummary> top_components;  ///< highest weights first
  std::uint32_t live_components = 0;
  Vec3 moment = Vec3::Zero();                   ///< estimated magnetic moment in G (A m^2)
};

}  // namespace sarloc::avalanche
