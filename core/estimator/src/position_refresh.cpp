#include "sarloc/core/estimator/position_refresh.hpp"

#include <algorithm>
#include <stdexcept>

namespace sarloc::estimator {

PositionRefresh::PositionRefresh(Clock::duration interval) : interval_(interval) {
  if (interval <= Clock::duration::zero()) throw std::invalid_argument("PositionRefresh: interval must be > 0");
}

void PositionRefresh::written(const responder::ResponderPosition& position, Clock::time_point at) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto [it, inserted] = held_.try_emplace(position.responder_id, Held{position, at});
  if (inserted) return;
  if (position.stamp < it->second.position.stamp) return;  // an older one overtaken on the way
  it->second = Held{position, at};
}

std::vector<responder::ResponderPosition> PositionRefresh::due(Clock::time_point now) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Held*> late;
  for (auto& [id, held] : held_) {
    if (now - held.written_at >= interval_) late.push_back(&held);
  }
  std::sort(late.begin(), late.end(), [](const Held* a, const Held* b) { return a->written_at < b->written_at; });
  std::vector<responder::ResponderPosition> out;
  out.reserve(late.size());
  for (Held* held : late) {
    out.push_back(held->position);
    held->written_at = now;
  }
  return out;
}

void PositionRefresh::forget(const std::string& responder_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  held_.erase(responder_id);
}

std::size_t PositionRefresh::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return held_.size();
}

}  // namespace sarloc::estimator
