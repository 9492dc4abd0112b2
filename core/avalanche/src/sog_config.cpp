#include "sarloc/core/avalanche/sog_filter.hpp"

#include <cmath>
#include <string>

#include "sarloc/core/common/validate.hpp"
#include "sog_filter_detail.hpp"

namespace sarloc::avalanche {
namespace {

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

void SogConfig::validate() const {
  require(initial_components != 0, "sog.initial_components", initial_components, "must be > 0");
  require(initial_components <= max_components, "sog.initial_components", initial_components,
          "must be <= max_components");
  require(max_components != 0, "sog.max_components", max_components, "must be > 0");
  require(near_field_initial_components != 0, "sog.near_field_initial_components", near_field_initial_components,
          "must be > 0");
  require(near_field_initial_components <= max_components, "sog.near_field_initial_components",
          near_field_initial_components, "must be <= max_components");
  standard.validate("sog.standard");
  require(std::isfinite(antenna_height_m) && antenna_height_m >= 0.0 && antenna_height_m <= 10.0,
          "sog.antenna_height_m", antenna_height_m, "must be in [0, 10]");
  require(finite_positive(max_burial_depth_m) && max_burial_depth_m <= 20.0, "sog.max_burial_depth_m",
          max_burial_depth_m, "must be in (0, 20]");
  require(depth_layers != 0 && depth_layers <= 20, "sog.depth_layers", depth_layers, "must be in [1, 20]");
  require(finite_positive(depth_sigma_factor) && depth_sigma_factor <= 5.0, "sog.depth_sigma_factor",
          depth_sigma_factor, "must be in (0, 5]");
  require(std::isfinite(near_field_depth_sigma_per_range) && near_field_depth_sigma_per_range >= 0.0 &&
              near_field_depth_sigma_per_range <= 1.0,
          "sog.near_field_depth_sigma_per_range", near_field_depth_sigma_per_range, "must be in [0, 1]");
  require(finite_positive(near_field_burial_depth_m) && near_field_burial_depth_m <= 20.0,
          "sog.near_field_burial_depth_m", near_field_burial_depth_m, "must be in (0, 20]");
  require(finite_positive(horizontal_overlap) && horizontal_overlap <= 5.0, "sog.horizontal_overlap",
          horizontal_overlap, "must be in (0, 5]");
  require(finite_positive(max_range_m) && max_range_m <= 500.0, "sog.max_range_m", max_range_m, "must be in (0, 500]");
  require(std::isfinite(range_noise_sigmas) && range_noise_sigmas >= 0.0 && range_noise_sigmas <= 10.0,
          "sog.range_noise_sigmas", range_noise_sigmas, "must be in [0, 10]");
  require(std::isfinite(moment_margin) && moment_margin >= 0.0 && moment_margin < 1.0, "sog.moment_margin",
          moment_margin, "must be in [0, 1)");
  for (int i = 0; i < 3; ++i) {
    // The whole vector in the message: which of the three is wrong is plain to read.
    if (!(finite_positive(attitude_prior_sigma_rad[i]) && attitude_prior_sigma_rad[i] <= kPi)) {
      detail::throw_config_error("sog.attitude_prior_sigma_rad", sog_detail::vec_text(attitude_prior_sigma_rad),
                                 "each must be in (0, pi]");
    }
  }
  require(std::isfinite(noise_relative) && noise_relative >= 0.0 && noise_relative <= 1.0, "sog.noise_relative",
          noise_relative, "must be in [0, 1]");
  require(finite_positive(censored_axis_sigmas) && censored_axis_sigmas <= 20.0, "sog.censored_axis_sigmas",
          censored_axis_sigmas, "must be in (0, 20]");
  require(std::isfinite(calibration_gain_sigma) && calibration_gain_sigma >= 0.0 && calibration_gain_sigma <= 0.3,
          "sog.calibration_gain_sigma", calibration_gain_sigma, "must be in [0, 0.3]");
  require(std::isfinite(calibration_pointing_sigma_deg) && calibration_pointing_sigma_deg >= 0.0 &&
              calibration_pointing_sigma_deg <= 20.0,
          "sog.calibration_pointing_sigma_deg", calibration_pointing_sigma_deg, "must be in [0, 20]");
  require(std::isfinite(field_carrier_hz) && field_carrier_hz >= 0.0 && field_carrier_hz <= 1e7, "sog.field_carrier_hz",
          field_carrier_hz, "must be in [0, 1e7] (0: the quasi-static field)");
  require(finite_positive(noise_floor_A_per_m) && noise_floor_A_per_m <= 1e-3, "sog.noise_floor_A_per_m",
          noise_floor_A_per_m, "must be in (0, 1e-3]");
  require(finite_positive(idle_translation_sigma_m) && idle_translation_sigma_m <= 10.0, "sog.idle_translation_sigma_m",
          idle_translation_sigma_m, "must be in (0, 10]");
  require(finite_positive(idle_rotation_sigma_rad) && idle_rotation_sigma_rad <= kPi, "sog.idle_rotation_sigma_rad",
          idle_rotation_sigma_rad, "must be in (0, pi]");
  require(finite_positive(prune_log_weight) && prune_log_weight <= 700.0, "sog.prune_log_weight", prune_log_weight,
          "must be in (0, 700]");
  require(finite_positive(merge_cell_m) && merge_cell_m <= 100.0, "sog.merge_cell_m", merge_cell_m,
          "must be in (0, 100]");
  require(std::isfinite(merge_mahalanobis) && merge_mahalanobis >= 0.0 && merge_mahalanobis <= 100.0,
          "sog.merge_mahalanobis", merge_mahalanobis, "must be in [0, 100]");
  require(reinit_gate_probability > 0.5 && reinit_gate_probability < 1.0, "sog.reinit_gate_probability",
          reinit_gate_probability, "must be in (0.5, 1)");
  require(iterated_update_max <= 20, "sog.iterated_update_max", iterated_update_max, "must be in [0, 20]");
  require(finite_positive(relinearise_threshold_sigmas) && relinearise_threshold_sigmas <= 100.0,
          "sog.relinearise_threshold_sigmas", relinearise_threshold_sigmas, "must be in (0, 100]");
  require(leap_gate_probability == 0.0 || (leap_gate_probability > 0.5 && leap_gate_probability < 1.0),
          "sog.leap_gate_probability", leap_gate_probability, "must be 0 (off) or in (0.5, 1)");
  require(std::isfinite(leap_min_range_m) && leap_min_range_m >= 0.0 && leap_min_range_m <= 100.0,
          "sog.leap_min_range_m", leap_min_range_m, "must be in [0, 100]");
  require(window_fit_samples == 0 || (window_fit_samples >= 4 && window_fit_samples <= 200), "sog.window_fit_samples",
          window_fit_samples, "must be 0 (off) or in [4, 200]");
  require(window_region_probability > 0.5 && window_region_probability < 1.0, "sog.window_region_probability",
          window_region_probability, "must be in (0.5, 1)");
  require(implausible_rebuild_steps <= 10000, "sog.implausible_rebuild_steps", implausible_rebuild_steps,
          "must be in [0, 10000]");
  require(converged_divergence_ratio >= 1.0 && converged_divergence_ratio <= 1e6, "sog.converged_divergence_ratio",
          converged_divergence_ratio, "must be in [1, 1e6]");
  require(divergence_window <= 100, "sog.divergence_window", divergence_window, "must be in [0, 100]");
  require(finite_positive(converged_radius_m) && converged_radius_m <= 1000.0, "sog.converged_radius_m",
          converged_radius_m, "must be in (0, 1000]");
  require(finite_positive(miss_detection_statistic) && miss_detection_statistic <= 1e4, "sog.miss_detection_statistic",
          miss_detection_statistic, "must be in (0, 1e4]");
  require(finite_positive(miss_power_margin) && miss_power_margin <= 1.0, "sog.miss_power_margin", miss_power_margin,
          "must be in (0, 1] (a miss never tells more than the model)");
  require(finite_positive(miss_weight_floor) && miss_weight_floor <= 1.0, "sog.miss_weight_floor", miss_weight_floor,
          "must be in (0, 1]");
}

SogConfig SogConfig::quasi_static() const {
  SogConfig c = *this;
  c.field_carrier_hz = 0.0;
  c.calibration_gain_sigma = 0.0;
  c.calibration_pointing_sigma_deg = 0.0;
  return c;
}

CalibrationVec SogConfig::calibration_variance() const {
  const double pointing = calibration_pointing_sigma_deg * kPi / 180.0;
  CalibrationVec v;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      v[3 * a + b] = a == b ? calibration_gain_sigma * calibration_gain_sigma : pointing * pointing;
  return v;
}

}  // namespace sarloc::avalanche
