#pragma once
// One weighted hypothesis of where a transmitter is and how it points: a Gaussian's mean, a
// particle or a grid cell. The search control reads a filter's posterior through these
// (BearingDensity, lookahead_heading), whatever the filter is.
#include <vector>

#include "sarloc/core/common/types.hpp"

namespace sarloc::avalanche {

struct TransmitterHypothesis {
  Vec3 position = Vec3::Zero();  ///< transmitter in G_k (m)
  Vec3 moment = Vec3::Zero();    ///< A m^2 in G_k
  double weight = 0.0;           ///< the weights of one filter sum to 1
};

}  // namespace sarloc::avalanche
