#include "sarloc/core/incident/incident_transform.hpp"

namespace sarloc::incident {

GaussianPosition to_incident_frame(const GaussianPosition& relative,
                                   const GaussianPosition& rescuer_antenna) {
  GaussianPosition out;
  out.position = rescuer_antenna.position + relative.position;
  out.covariance = relative.covariance + rescuer_antenna.covariance;
  out.covariance = 0.5 * (out.covariance + out.covariance.transpose()).eval();
  return out;
}

}  // namespace sarloc::incident
