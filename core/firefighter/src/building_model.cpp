#include "sarloc/core/firefighter/building_model.hpp"

namespace sarloc::firefighter {

BuildingModel::BuildingModel(FloorPlan plan, BuildingModelConfig config)
    : plan_(std::move(plan)), config_(std::move(config)) {
  plan_.validate();
  config_.validate();
  grid_ = navigable_grid(plan_, config_.grid);
  matcher_ = std::make_unique<PatternMatcher>(extract_node_sequences(plan_, config_.grid), config_.grid,
                                              config_.pattern);
}

}  // namespace sarloc::firefighter
