#include "sarloc/core/avalanche/sog_filter.hpp"

#include <cmath>
#include <string>

#include "sarloc/core/common/validate.hpp"
#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {
namespace {

template <typename T>
[[noreturn]] void config_fail(const char* key, const T& value, const char* rule) {
  detail::throw_config_error(std::string("sog.") + key, config_value(static_cast<double>(value)), rule);
}

[[noreturn]] void config_fail(const char* key, const std::string& value_text, const char* rule) {
  detail::throw_config_error(std::string("sog.") + key, value_text, rule);
}

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

void SogConfig::validate() const {
  if (initial_components == 0) config_fail("initial_components", initial_components, "must be > 0");
  if (initial_components > max_components)
    config_fail("initial_components", initial_components, "must be <= max_components");
  if (max_components == 0) config_fail("max_components", max_components, "must be > 0");
  standard.validate("sog.standard");
  if (!std::isfinite(antenna_height_m) || antenna_height_m < 0.0 || antenna_height_m > 10.0)
    config_fail("antenna_height_m", antenna_height_m, "must be in [0, 10]");
  if (!finite_positive(max_burial_depth_m) || max_burial_depth_m > 20.0)
    config_fail("max_burial_depth_m", max_burial_depth_m, "must be in (0, 20]");
  if (depth_layers == 0 || depth_layers > 20)
    config_fail("depth_layers", depth_layers, "must be in [1, 20]");
  if (!finite_positive(depth_sigma_factor) || depth_sigma_factor > 5.0)
    config_fail("depth_sigma_factor", depth_sigma_factor, "must be in (0, 5]");
  if (!std::isfinite(near_field_depth_sigma_per_range) || near_field_depth_sigma_per_range < 0.0 ||
      near_field_depth_sigma_per_range > 1.0)
    config_fail("near_field_depth_sigma_per_range", near_field_depth_sigma_per_range, "must be in [0, 1]");
  if (!finite_positive(near_field_burial_depth_m) || near_field_burial_depth_m > 20.0)
    config_fail("near_field_burial_depth_m", near_field_burial_depth_m, "must be in (0, 20]");
  if (!finite_positive(horizontal_overlap) || horizontal_overlap > 5.0)
    config_fail("horizontal_overlap", horizontal_overlap, "must be in (0, 5]");
  if (!finite_positive(max_range_m) || max_range_m > 500.0)
    config_fail("max_range_m", max_range_m, "must be in (0, 500]");
  if (!std::isfinite(range_noise_sigmas) || range_noise_sigmas < 0.0 || range_noise_sigmas > 10.0)
    config_fail("range_noise_sigmas", range_noise_sigmas, "must be in [0, 10]");
  if (!std::isfinite(moment_margin) || moment_margin < 0.0 || moment_margin >= 1.0)
    config_fail("moment_margin", moment_margin, "must be in [0, 1)");
  for (int i = 0; i < 3; ++i) {
    if (!finite_positive(attitude_prior_sigma_rad[i]) || attitude_prior_sigma_rad[i] > kPi)
      config_fail("attitude_prior_sigma_rad", sog_detail::vec_text(attitude_prior_sigma_rad),
                  "each must be in (0, pi]");
  }
  if (!std::isfinite(noise_relative) || noise_relative < 0.0 || noise_relative > 1.0)
    config_fail("noise_relative", noise_relative, "must be in [0, 1]");
  if (!finite_positive(censored_axis_sigmas) || censored_axis_sigmas > 20.0)
    config_fail("censored_axis_sigmas", censored_axis_sigmas, "must be in (0, 20]");
  if (!finite_positive(noise_floor_A_per_m) || noise_floor_A_per_m > 1e-3)
    config_fail("noise_floor_A_per_m", noise_floor_A_per_m, "must be in (0, 1e-3]");
  if (!finite_positive(idle_translation_sigma_m) || idle_translation_sigma_m > 10.0)
    config_fail("idle_translation_sigma_m", idle_translation_sigma_m, "must be in (0, 10]");
  if (!finite_positive(idle_rotation_sigma_rad) || idle_rotation_sigma_rad > kPi)
    config_fail("idle_rotation_sigma_rad", idle_rotation_sigma_rad, "must be in (0, pi]");
  if (!finite_positive(prune_log_weight) || prune_log_weight > 700.0)
    config_fail("prune_log_weight", prune_log_weight, "must be in (0, 700]");
  if (!finite_positive(merge_cell_m) || merge_cell_m > 100.0)
    config_fail("merge_cell_m", merge_cell_m, "must be in (0, 100]");
  if (!std::isfinite(merge_mahalanobis) || merge_mahalanobis < 0.0 || merge_mahalanobis > 100.0)
    config_fail("merge_mahalanobis", merge_mahalanobis, "must be in [0, 100]");
  if (!(reinit_gate_probability > 0.5 && reinit_gate_probability < 1.0))
    config_fail("reinit_gate_probability", reinit_gate_probability, "must be in (0.5, 1)");
  if (iterated_update_max > 20)
    config_fail("iterated_update_max", iterated_update_max, "must be in [0, 20]");
  if (!finite_positive(relinearise_threshold_sigmas) || relinearise_threshold_sigmas > 100.0)
    config_fail("relinearise_threshold_sigmas", relinearise_threshold_sigmas, "must be in (0, 100]");
  if (!(leap_gate_probability == 0.0 || (leap_gate_probability > 0.5 && leap_gate_probability < 1.0)))
    config_fail("leap_gate_probability", leap_gate_probability, "must be 0 (off) or in (0.5, 1)");
  if (!std::isfinite(leap_min_range_m) || leap_min_range_m < 0.0 || leap_min_range_m > 100.0)
    config_fail("leap_min_range_m", leap_min_range_m, "must be in [0, 100]");
  if (implausible_rebuild_steps > 10000)
    config_fail("implausible_rebuild_steps", implausible_rebuild_steps, "must be in [0, 10000]");
  if (!(converged_divergence_ratio >= 1.0 && converged_divergence_ratio <= 1e6))
    config_fail("converged_divergence_ratio", converged_divergence_ratio, "must be in [1, 1e6]");
  if (divergence_window > 100)
    config_fail("divergence_window", divergence_window, "must be in [0, 100]");
  if (!finite_positive(converged_radius_m) || converged_radius_m > 1000.0)
    config_fail("converged_radius_m", converged_radius_m, "must be in (0, 1000]");
  if (!finite_positive(miss_detection_statistic) || miss_detection_statistic > 1e4)
    config_fail("miss_detection_statistic", miss_detection_statistic, "must be in (0, 1e4]");
  if (!finite_positive(miss_power_margin) || miss_power_margin > 1.0)
    config_fail("miss_power_margin", miss_power_margin, "must be in (0, 1] (a miss never tells more than the model)");
  if (!finite_positive(miss_weight_floor) || miss_weight_floor > 1.0)
    config_fail("miss_weight_floor", miss_weight_floor, "must be in (0, 1]");
}

}  // namespace sarloc::avalanche
