#include "sarloc/core/avalanche/field_measurement_check.hpp"
#include "sarloc/core/avalanche/transmitter_filter.hpp"

#include <algorithm>
#include <numeric>

#include "sarloc/core/avalanche/sog_filter.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/gaussian.hpp"

namespace sarloc::avalanche {

MixtureMoments moved_moments(const MixtureMoments& moments, const Displacement& d) {
  MixtureMoments mm = moments;
  if (d.samples == 0) return mm;
  CompositionJacobians f;
  mm.mean = CompositionModel::f(mm.mean, d.mean, &f);  // eq. (9) on the mean
  mm.covariance.block<3, 3>(idx::kPos, idx::kPos) +=
      f.pos_trans * d.covariance.block<3, 3>(idx::kTrans, idx::kTrans) * f.pos_trans.transpose();
  return mm;
}

Vec3 moved_point(const MixtureMoments& moments, const Vec3& point, const DispVec& d) {
  StateVec origin = moments.mean;  // the rescuer's attitude turns the step into G
  origin.segment<3>(idx::kPos) = point;
  return CompositionModel::f(origin, d, static_cast<CompositionJacobians*>(nullptr)).segment<3>(idx::kPos);
}

void check_sample(const FieldMeasurement& measurement, const std::string& rescuer_id,
                  const std::optional<std::uint64_t>& last_sequence) {
  validate_field_measurement(measurement);
  if (!rescuer_id.empty() && !measurement.rescuer_id.empty() && measurement.rescuer_id != rescuer_id)
    throw InputError("field_measurement.rescuer_id = " + measurement.rescuer_id + ": filter belongs to " + rescuer_id);
  if (last_sequence && measurement.sequence <= *last_sequence)
    throw InputError("field_measurement.sequence = " + std::to_string(measurement.sequence) + ": must be > previous " +
                     std::to_string(*last_sequence));
}

VictimEstimate estimate_from(const MixtureMoments& moments, std::size_t hypotheses, double converged_radius_m,
                             std::size_t top_k, const std::function<double(std::size_t)>& weight_of,
                             const std::function<MixtureComponentSummary(std::size_t)>& summary_of) {
  VictimEstimate e;
  e.live_components = static_cast<std::uint32_t>(hypotheses);
  if (hypotheses == 0) {
    e.status = EstimatorStatus::kInitialising;
    return e;
  }
  e.relative.position = moments.mean.segment<3>(idx::kPos);
  e.relative.covariance = moments.covariance.block<3, 3>(idx::kPos, idx::kPos);
  e.moment = moments.mean.segment<3>(idx::kMom);
  e.status = radius95_3d(e.relative.covariance) <= converged_radius_m ? EstimatorStatus::kConverged
                                                                      : EstimatorStatus::kMultimodal;
  const std::size_t k = std::min(top_k, hypotheses);
  if (k == 0) return e;
  std::vector<std::size_t> order(hypotheses);
  std::iota(order.begin(), order.end(), 0);
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                    [&](std::size_t a, std::size_t b) { return weight_of(a) > weight_of(b); });
  for (std::size_t i = 0; i < k; ++i) e.top_components.push_back(summary_of(order[i]));
  return e;
}

bool moment_plausible_from(const MixtureMoments& moments, const TransmitterStandard& standard, double margin) {
  return standard.allows(moments.mean.segment<3>(idx::kMom), moments.covariance.block<3, 3>(idx::kMom, idx::kMom),
                         margin);
}

}  // namespace sarloc::avalanche
