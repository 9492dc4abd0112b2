#pragma once
// The avalanche rescuer's estimator: avalanche::RescuerSearch (one SOG filter and search
// controller per separated beacon signal) behind the ResponderEstimator interface.
#include "sarloc/core/avalanche/rescuer_search.hpp"
#include "sarloc/core/estimator/responder_estimator.hpp"

namespace sarloc::estimator {

class AvalancheRescuerEstimator final : public ResponderEstimator {
 public:
  AvalancheRescuerEstimator(std::string rescuer_id, avalanche::RescuerSearchConfig config);

  ResponderRole role() const override { return ResponderRole::kAvalancheRescuer; }
  const std::string& responder_id() const override { return search_.rescuer_id(); }
  Outcome add_odometry(const responder::Odometry& odometry) override;
  bool add_unknown_motion(TimestampNs from, TimestampNs until) override;
  /// FieldMeasurement samples; anything else is refused (kWrongRole).
  Outcome process(const SensorSample& sample) override;
  std::optional<responder::Guidance> coast(TimestampNs stamp) override;
  void mark_done(std::uint32_t signal_id) override { search_.mark_done(signal_id); }
  void leave_to_others(std::set<std::uint32_t> signal_ids, TimestampNs until) override {
    search_.leave_to_others(std::move(signal_ids), until);
  }
  std::optional<responder::VictimEstimate> estimate_of(std::uint32_t signal_id) const override {
    return search_.estimate(signal_id);
  }
  std::optional<avalanche::FieldFit> field_fit(std::uint32_t signal_id, const Vec3& field, const Vec3& noise,
                                               std::uint8_t axes) const override {
    return search_.field_fit(signal_id, field, noise, axes);
  }
  std::size_t active_filters() const override { return search_.signal_count(); }

  const avalanche::RescuerSearch& search() const { return search_; }

 private:
  avalanche::RescuerSearch search_;
};

}  // namespace sarloc::estimator
