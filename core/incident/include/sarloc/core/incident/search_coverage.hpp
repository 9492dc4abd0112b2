#pragma once
// Which parts of the deposit have been searched (issue 63, item 2): a grid of cells over the
// deposit, a cell searched once a rescuer's track passed within half a strip width of its
// centre (a transmitter there would have been heard). Per strip, so that incident command can
// re-plan what is left when a rescuer leaves or is lost.
//
//   SearchCoverage c(deposit, strips, 1.0);
//   c.add_walk(from, to, 0.5 * strip_width_m);
//   c.searched(); c.searched(strip_index);
#include <cstdint>
#include <vector>

#include "sarloc/core/incident/deposit.hpp"
#include "sarloc/core/incident/search_strips.hpp"

namespace sarloc::incident {

class SearchCoverage {
 public:
  /// `cell_m`: the grid's cell (0.5-5 m); InputError otherwise.
  SearchCoverage(const Deposit& deposit, const std::vector<Strip>& strips, double cell_m);

  /// A rescuer walked from `a` to `b` hearing `reach_m` to either side. InputError for a
  /// non-finite point or reach.
  void add_walk(const Vec2& a, const Vec2& b, double reach_m);

  /// What `before`, a coverage over another outline of the deposit (an operator redrew it),
  /// found searched: each of this grid's cells whose centre lies in a searched cell of
  /// `before` is searched. A cell outside the old outline is not (nobody walked there for it).
  void carry_over(const SearchCoverage& before);

  /// Whether the cell holding `p` is searched (a point outside the deposit counts as searched:
  /// nothing there to search).
  bool searched_at(const Vec2& p) const;
  /// The same for a walker of `strip`: a cell of another strip counts as searched too (its own
  /// walker's). Without it, a row that reaches the neighbour's boundary cells waited for the
  /// neighbour: one rescuer leaving for a signal stopped the strips on either side.
  bool searched_at(const Vec2& p, std::size_t strip) const;
  double searched() const;                   ///< fraction of the deposit's cells searched
  double searched(std::size_t strip) const;  ///< ... of one strip's cells (1 for a strip with none)
  std::size_t cells() const { return centres_.size(); }

 private:
  std::int32_t cell_at(const Vec2& p) const;  ///< centres_ index, -1 outside the deposit
  std::vector<Vec2> centres_;           // cells inside the deposit
  std::vector<std::int32_t> strip_of_;  // per cell, -1: in no strip
  std::vector<char> searched_;
  std::vector<std::size_t> strip_cells_;
  std::vector<std::size_t> strip_searched_;
  std::size_t searched_count_ = 0;
  Vec2 origin_ = Vec2::Zero();
  double cell_m_ = 1.0;
  std::size_t columns_ = 0, rows_ = 0;
  std::vector<std::int32_t> index_;  // grid cell -> centres_ index, -1 outside
};

}  // namespace sarloc::incident
