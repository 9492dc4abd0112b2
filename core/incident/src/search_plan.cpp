#include "sarloc/core/incident/search_plan.hpp"

#include <algorithm>
#include <cmath>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::incident {

void SearchPlanConfig::validate() const {
  strips.validate();
  require(std::isfinite(coverage_cell_m) && coverage_cell_m >= 0.5 && coverage_cell_m <= 5.0, "search.coverage_cell_m",
          coverage_cell_m, "must be in [0.5, 5]");
  require(std::isfinite(strip_done_fraction) && strip_done_fraction >= 0.5 && strip_done_fraction <= 1.0,
          "search.strip_done_fraction", strip_done_fraction, "must be in [0.5, 1]");
  require(std::isfinite(max_walk_step_m) && max_walk_step_m >= 2.0 && max_walk_step_m <= 100.0,
          "search.max_walk_step_m", max_walk_step_m, "must be in [2, 100]");
  require(std::isfinite(recut_below_searched) && recut_below_searched >= 0.0 && recut_below_searched <= 0.5,
          "search.recut_below_searched", recut_below_searched, "must be in [0, 0.5]");
  require(std::isfinite(pursuit_timeout_s) && pursuit_timeout_s >= 30.0 && pursuit_timeout_s <= 3600.0,
          "search.pursuit_timeout_s", pursuit_timeout_s, "must be in [30, 3600]");
}

SearchPlanner::SearchPlanner(Deposit deposit, SearchPlanConfig config)
    : deposit_(std::move(deposit)), config_((config.validate(), config)) {}

SearchPlanner::SearchPlanner(Deposit deposit, SearchPlanConfig config, const SearchPlanner& before)
    : SearchPlanner(std::move(deposit), std::move(config)) {
  inherited_ = before.coverage_;
  if (before.inherited_ && !before.coverage_) inherited_ = before.inherited_;  // redrawn twice before a cut
}

void SearchPlanner::on_position(const std::string& rescuer_id, const Vec2& position) {
  if (!position.allFinite()) throw InputError("search plan: " + rescuer_id + "'s position is not finite");
  Rescuer& r = rescuers_[rescuer_id];
  if (r.last && (position - *r.last).norm() <= config_.max_walk_step_m) {
    // Half the strip width the plan was made for: the hearing range it assumes (not the width
    // of strips cut narrower for more rescuers).
    const double reach = 0.5 * config_.strips.strip_width_m;
    if (coverage_) coverage_->add_walk(*r.last, position, reach);
    if (may_recut_) walks_.emplace_back(*r.last, position);
    if (walks_.size() > kRecutWalksMax) {  // memory stays bounded; the strips stay as cut
      may_recut_ = false;
      walks_.clear();
      walks_.shrink_to_fit();
    }
  }
  r.last = position;
}

void SearchPlanner::release(const std::string& rescuer_id) {
  rescuers_[rescuer_id].searching = false;
  for (auto& s : plan_.strips) {
    if (s.rescuer_id == rescuer_id) {
      s.rescuer_id.clear();
      ++plan_.revision;
    }
    if (s.helper_id == rescuer_id) {
      s.helper_id.clear();
      ++plan_.revision;
    }
  }
}

void SearchPlanner::resume(const std::string& rescuer_id) { rescuers_[rescuer_id].searching = true; }

std::size_t SearchPlanner::searching_with_fix() const {
  std::size_t n = 0;
  for (const auto& [id, r] : rescuers_) n += r.searching && r.last ? 1 : 0;
  return n;
}

void SearchPlanner::cut(std::size_t searching_rescuers) {
  Vec2 entry = Vec2::Zero();
  for (const auto& [id, r] : rescuers_)
    if (r.searching && r.last) entry += *r.last;
  entry /= static_cast<double>(searching_rescuers);
  const auto strips = plan_strips(deposit_, config_.strips, entry, std::min(searching_rescuers, kSearchStripsMax));
  coverage_.emplace(deposit_, strips, config_.coverage_cell_m);
  const double reach = 0.5 * config_.strips.strip_width_m;
  for (const auto& [a, b] : walks_) coverage_->add_walk(a, b, reach);
  if (inherited_) coverage_->carry_over(*inherited_);
  plan_.strips.clear();
  for (const Strip& s : strips) plan_.strips.push_back({s, 0.0, "", false, ""});
  first_open_row_.assign(strips.size(), 0);
  last_open_row_.assign(strips.size(), 0);
}

bool SearchPlanner::update() {
  const std::uint32_t before = plan_.revision;
  const std::size_t searching = searching_with_fix();
  if (searching == 0 && !coverage_) return false;
  // Cut, or re-cut for rescuers who arrived while the search had barely begun.
  if (may_recut_ && searching > 0 && (!coverage_ || coverage_->searched() < config_.recut_below_searched)) {
    const bool first = !coverage_;
    if (first || searching > cut_for_) {  // more rescuers than the strips were cut for
      const std::size_t had = plan_.strips.size();
      cut(searching);
      cut_for_ = searching;
      if (first || plan_.strips.size() != had) ++plan_.revision;
    }
  }
  if (coverage_ && coverage_->searched() >= config_.recut_below_searched) {
    may_recut_ = false;
    walks_.clear();
    walks_.shrink_to_fit();
    inherited_.reset();  // no cut will take it over again
  }
  for (std::size_t i = 0; i < plan_.strips.size(); ++i) {
    PlannedStrip& s = plan_.strips[i];
    s.searched = coverage_->searched(i);
    // Done, or no row across it left unsearched (its last cells: slivers off its band).
    const bool done = s.searched >= config_.strip_done_fraction || !first_unsearched(i);
    if (done && !s.done) {
      s.done = true;
      s.rescuer_id.clear();  // both free for an open strip
      s.helper_id.clear();
      ++plan_.revision;
    }
  }
  plan_.searched = coverage_->searched();
  // Free searching rescuers to open strips.
  std::vector<std::string> free_ids;
  std::vector<Vec2> free_at;
  for (const auto& [id, r] : rescuers_) {
    if (!r.searching || !r.last || strip_of(id) || strip_helped_by(id)) continue;
    free_ids.push_back(id);
    free_at.push_back(*r.last);
  }
  std::vector<bool> open;
  std::vector<Strip> strips;
  for (const auto& s : plan_.strips) {
    open.push_back(!s.done && s.rescuer_id.empty());
    strips.push_back(s.strip);
  }
  std::vector<std::string> still_free_ids;
  std::vector<Vec2> still_free_at;
  if (!free_ids.empty() && std::find(open.begin(), open.end(), true) != open.end()) {
    const auto chosen = assign_strips(strips, free_at, open);
    for (std::size_t k = 0; k < free_ids.size(); ++k) {
      if (!chosen[k]) {
        still_free_ids.push_back(free_ids[k]);
        still_free_at.push_back(free_at[k]);
        continue;
      }
      plan_.strips[*chosen[k]].rescuer_id = free_ids[k];
      ++plan_.revision;
    }
  } else {
    still_free_ids = std::move(free_ids);
    still_free_at = std::move(free_at);
  }
  assign_helpers(std::move(still_free_ids), std::move(still_free_at));
  return plan_.revision != before;
}

void SearchPlanner::assign_helpers(std::vector<std::string> free_ids, std::vector<Vec2> free_at) {
  // Strips walked from the top, not done, without a helper: the unsearched stretch between the
  // walker's next point and the bottom one (L).
  struct Helpable {
    std::size_t strip;
    Vec2 bottom;
    double left_m;
  };
  std::vector<Helpable> helpable;
  for (std::size_t i = 0; i < plan_.strips.size(); ++i) {
    const PlannedStrip& s = plan_.strips[i];
    if (s.done || s.rescuer_id.empty() || !s.helper_id.empty()) continue;
    const auto top = first_unsearched(i), bottom = first_unsearched(i, true);
    if (top && bottom) helpable.push_back({i, *bottom, (*bottom - *top).norm()});
  }
  // The largest saving L - D first, while any is positive.
  while (!free_ids.empty() && !helpable.empty()) {
    double best = 0.0;
    std::size_t best_rescuer = 0, best_strip = 0;
    for (std::size_t r = 0; r < free_ids.size(); ++r)
      for (std::size_t h = 0; h < helpable.size(); ++h) {
        const double saving = helpable[h].left_m - (helpable[h].bottom - free_at[r]).norm();
        if (saving > best) {
          best = saving;
          best_rescuer = r;
          best_strip = h;
        }
      }
    if (best <= 0.0) return;
    plan_.strips[helpable[best_strip].strip].helper_id = free_ids[best_rescuer];
    ++plan_.revision;
    free_ids.erase(free_ids.begin() + static_cast<std::ptrdiff_t>(best_rescuer));
    free_at.erase(free_at.begin() + static_cast<std::ptrdiff_t>(best_rescuer));
    helpable.erase(helpable.begin() + static_cast<std::ptrdiff_t>(best_strip));
  }
}

bool SearchPlanner::adopt_assignments(const SearchPlan& active) {
  if (active.strips.size() != plan_.strips.size()) return false;
  for (std::size_t i = 0; i < plan_.strips.size(); ++i) {
    const Strip& a = active.strips[i].strip;
    const Strip& own = plan_.strips[i].strip;
    if ((a.top - own.top).norm() > 0.5 || (a.bottom - own.bottom).norm() > 0.5) return false;
  }
  bool changed = false;
  for (std::size_t i = 0; i < plan_.strips.size(); ++i) {
    PlannedStrip& own = plan_.strips[i];
    const PlannedStrip& a = active.strips[i];
    if (own.rescuer_id != a.rescuer_id || own.helper_id != a.helper_id || (a.done && !own.done)) changed = true;
    own.rescuer_id = a.rescuer_id;
    own.helper_id = a.helper_id;
    own.done = own.done || a.done;
  }
  plan_.revision = std::max(plan_.revision + (changed ? 1U : 0U), active.revision);
  return true;
}

std::optional<std::size_t> SearchPlanner::strip_of(const std::string& rescuer_id) const {
  for (std::size_t i = 0; i < plan_.strips.size(); ++i)
    if (plan_.strips[i].rescuer_id == rescuer_id) return i;
  return std::nullopt;
}

std::optional<std::size_t> SearchPlanner::strip_helped_by(const std::string& rescuer_id) const {
  for (std::size_t i = 0; i < plan_.strips.size(); ++i)
    if (plan_.strips[i].helper_id == rescuer_id) return i;
  return std::nullopt;
}

std::optional<Vec2> SearchPlanner::next_point(const std::string& rescuer_id) const {
  if (const auto strip = strip_of(rescuer_id)) return first_unsearched(*strip);
  if (const auto helped = strip_helped_by(rescuer_id)) return first_unsearched(*helped, true);
  return std::nullopt;
}

SearchPlanPicture SearchPlanner::picture(const std::string& incident_id, std::int64_t stamp) const {
  SearchPlanPicture out;
  out.incident_id = incident_id;
  out.stamp = stamp;
  out.deposit = deposit_.vertices();
  out.plan = plan_;
  for (const auto& s : plan_.strips) {
    out.next_points.push_back(s.rescuer_id.empty() ? std::nullopt : next_point(s.rescuer_id));
    out.helper_next_points.push_back(s.helper_id.empty() ? std::nullopt : next_point(s.helper_id));
  }
  return out;
}

std::optional<Vec2> SearchPlanner::first_unsearched(std::size_t strip, bool from_bottom) const {
  if (!coverage_) return std::nullopt;
  // Down the centreline in cell steps (a helper: up), the first point whose row across the strip
  // still holds an unsearched cell: walking to it searches that row, the far corners included
  // (the centreline's own end is heard a reach before them). Coverage only grows, so the search
  // starts at the row found last time.
  const Strip& s = plan_.strips[strip].strip;
  const Vec2 start = from_bottom ? s.bottom : s.top, end = from_bottom ? s.top : s.bottom;
  const double cell = config_.coverage_cell_m;
  const double length = (end - start).norm();
  const Vec2 along = length > 0.0 ? Vec2((end - start) / length) : Vec2(0.0, from_bottom ? 1.0 : -1.0);
  const Vec2 across(-along.y(), along.x());
  const auto steps = static_cast<std::size_t>(std::ceil(length / cell));
  const auto half_cells = static_cast<int>(std::floor(0.5 * s.width_m / cell));
  std::size_t& k = from_bottom ? last_open_row_[strip] : first_open_row_[strip];
  for (; k <= steps; ++k) {
    const Vec2 p = start + along * std::min(length, cell * static_cast<double>(k));
    for (int j = -half_cells; j <= half_cells; ++j)
      if (!coverage_->searched_at(p + across * (cell * static_cast<double>(j)), strip)) return p;
  }
  return std::nullopt;
}

}  // namespace sarloc::incident
