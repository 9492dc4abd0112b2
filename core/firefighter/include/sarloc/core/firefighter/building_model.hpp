#pragma once
// Everything about one building that every firefighter's filter reads and none changes: the
// floor plan, its navigable grid and the pattern matcher over its search patterns. Built once
// per building (extracting and indexing the patterns of the 1040 m2 floor takes a second) and
// shared, read-only, by the filters of every firefighter in it.
//
//   auto building = std::make_shared<const BuildingModel>(load_floor_plan(path), BuildingModelConfig{});
//   IndoorLocalizer a(building, ...), b(building, ...);
#include <memory>

#include "sarloc/core/firefighter/floor_plan.hpp"
#include "sarloc/core/firefighter/pattern_matcher.hpp"
#include "sarloc/core/firefighter/search_pattern.hpp"

namespace sarloc::firefighter {

struct BuildingModelConfig {
  PatternGridConfig grid;
  PatternMatchConfig pattern;
  void validate() const {
    grid.validate();
    pattern.validate();
  }
};

class BuildingModel {
 public:
  /// Throws ConfigError for an invalid plan or configuration.
  BuildingModel(FloorPlan plan, BuildingModelConfig config);

  const FloorPlan& plan() const { return plan_; }
  const NavigableGrid& grid() const { return grid_; }
  const PatternMatcher& matcher() const { return *matcher_; }
  const BuildingModelConfig& config() const { return config_; }

 private:
  FloorPlan plan_;
  BuildingModelConfig config_;
  NavigableGrid grid_;
  std::unique_ptr<PatternMatcher> matcher_;
};

}  // namespace sarloc::firefighter
