#include "sarloc/app/firefighter_yaml.hpp"

#include <string>

namespace sarloc::app {

void read_map_filter(YamlReader section, firefighter::MapFilterConfig& filter) {
  section.read("particles", filter.particles);
  section.read("particles_max", filter.particles_max);
  section.read("kld_epsilon", filter.kld_epsilon);
  section.read("kld_confidence", filter.kld_confidence);
  section.read("kld_bin_m", filter.kld_bin_m);
  section.read("kld_bin_deg", filter.kld_bin_deg);
  section.read("position_noise_m", filter.position_noise_m);
  section.read("heading_noise_deg_per_m", filter.heading_noise_deg_per_m);
  section.read("moving_threshold_m", filter.moving_threshold_m);
  section.read("likelihood_sigma", filter.likelihood_sigma);
  section.read("likelihood_sigma_converged", filter.likelihood_sigma_converged);
  section.read("pattern_outlier_probability", filter.pattern_outlier_probability);
  section.read("entry_prior", filter.entry_prior);
  section.read("converged_entry_share", filter.converged_entry_share);
  section.read("weight_floor_factor", filter.weight_floor_factor);
  section.read("replace_fraction", filter.replace_fraction);
  section.read("replace_position_sigma_m", filter.replace_position_sigma_m);
  section.read("replace_heading_sigma_deg", filter.replace_heading_sigma_deg);
  std::string resampling = firefighter::to_string(filter.resampling);
  section.read("resampling", resampling);
  filter.resampling = firefighter::parse_pseudo_resampling(resampling, section.source() + ": " + (section.path().empty() ? "" : section.path() + ".") + "resampling");
  section.read("converged_variance_m2", filter.converged_variance_m2);
  section.read("entry_radius_m", filter.entry_radius_m);
  section.read("confirm_entry_share", filter.confirm_entry_share);
  section.read("confirm_after_steps", filter.confirm_after_steps);
  section.read("known_position_sigma_m", filter.known_position_sigma_m);
  section.read("known_heading_sigma_deg", filter.known_heading_sigma_deg);
  section.read("floor_tolerance_m", filter.floor_tolerance_m);
  section.read("map_error_removed_fraction", filter.map_error_removed_fraction);
  section.read("map_error_clear_updates", filter.map_error_clear_updates);
  section.read("map_error_spread_factor", filter.map_error_spread_factor);
  section.expect_done();
}

}  // namespace sarloc::app
