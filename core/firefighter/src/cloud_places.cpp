#include "sarloc/core/firefighter/cloud_places.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace sarloc::firefighter {
namespace {

constexpr double kCellM = 1.0;

}  // namespace

std::vector<Place> cloud_places(const std::vector<Particle>& particles, const std::vector<double>& weights) {
  struct Cell {
    std::size_t floor;
    std::int64_t ix, iy;
    std::vector<std::size_t> members;
    int place = -1;
  };
  std::unordered_map<std::uint64_t, Cell> cells;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (!(weights[i] > 0.0)) continue;
    const Particle& p = particles[i];
    const auto ix = static_cast<std::int64_t>(std::floor(p.position.x() / kCellM));
    const auto iy = static_cast<std::int64_t>(std::floor(p.position.y() / kCellM));
    auto [it, fresh] = cells.try_emplace(cell_key(p.floor, ix, iy), Cell{p.floor, ix, iy, {}, -1});
    it->second.members.push_back(i);
  }
  std::vector<std::vector<std::size_t>> groups;  // particle indices per place
  std::vector<Cell*> stack;
  for (auto& [key, start] : cells) {
    if (start.place >= 0) continue;
    start.place = static_cast<int>(groups.size());
    groups.emplace_back();
    stack.push_back(&start);
    while (!stack.empty()) {
      Cell* c = stack.back();
      stack.pop_back();
      groups.back().insert(groups.back().end(), c->members.begin(), c->members.end());
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const auto n = cells.find(cell_key(c->floor, c->ix + dx, c->iy + dy));
          if (n == cells.end() || n->second.place >= 0) continue;
          n->second.place = start.place;
          stack.push_back(&n->second);
        }
      }
    }
  }
  double total = 0.0;
  for (const double w : weights) total += w > 0.0 ? w : 0.0;
  std::vector<Place> places;
  for (const auto& members : groups) {
    Place place;
    place.floor = particles[members.front()].floor;
    for (const std::size_t i : members) {
      place.weight += weights[i];
      place.position += weights[i] * particles[i].position;
    }
    place.position /= place.weight;
    for (const std::size_t i : members) {
      const Vec2 d = particles[i].position - place.position;
      place.covariance += weights[i] * d * d.transpose();
    }
    place.covariance /= place.weight;
    place.weight /= total;
    places.push_back(place);
  }
  std::sort(places.begin(), places.end(), [](const Place& a, const Place& b) { return a.weight > b.weight; });
  return places;
}

}  // namespace sarloc::firefighter
