#include "sarloc/core/firefighter/search_walk.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "sarloc/core/common/angle.hpp"
#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"
#include "sarloc/core/firefighter/wall_index.hpp"

namespace sarloc::firefighter {
namespace {

constexpr double kStepM = 0.05;        // the walker's control step
constexpr double kSensorRangeM = 3.0;  // how far it feels for walls
constexpr double kMinClearanceM = 0.15;
constexpr double kCrawlStanceFraction = 0.75;

Vec2 dir(double heading) { return {std::cos(heading), std::sin(heading)}; }

class Walker {
 public:
  Walker(const FloorPlan& plan, const SearchWalkConfig& config, Hand hand, std::mt19937_64& rng)
      : plan_(plan), config_(config), hand_(hand), side_(hand == Hand::kRight ? -1.0 : 1.0), rng_(rng) {
    for (std::size_t f = 0; f < plan.floors.size(); ++f) {
      world_.push_back(std::make_unique<WallIndex>(plan.solid_walls(f, WallSet::kWorld)));
    }
  }

  SearchWalk run(const Entry& entry) {
    SearchWalk walk;
    walk.entry = entry.id;
    floor_ = plan_.floor_index(entry.floor);
    pos_ = entry.position;
    heading_ = stance_heading(entry, hand_);
    speed_ = uniform(config_.speed_min_mps, config_.speed_max_mps);
    offset_ = draw_offset();
    Footfall first;
    first.t_land = 0.0;
    first.stance_s = config_.standing_s;
    first.position = Eigen::Vector3d(pos_.x(), pos_.y(), height());
    first.yaw = heading_;
    first.floor = floor_;
    feet_.push_back(first);
    const double end = config_.standing_s + config_.duration_s;
    std::size_t guard = 0;
    while (time_ < end && ++guard < 2000000) control_step();
    walk.leader = feet_;
    walk.distance_m = path_length(feet_);
    walk.follower = follow(feet_);
    return walk;
  }

 private:
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  bool chance(double p) { return std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < p; }
  double draw_offset() { return uniform(config_.offset_min_m, config_.offset_max_m); }
  const WallIndex& world() const { return *world_[floor_]; }

  double height() const { return plan_.floors[floor_].elevation_m + stair_rise_; }

  // Time of the last footfall's lift-off: the next swing starts there.
  double lift_off() const { return feet_.back().t_land + feet_.back().stance_s; }

  void control_step() {
    const double dside = world().ray(pos_, heading_ + side_ * 0.5 * kPi, kSensorRangeM);
    const double dfront = world().ray(pos_, heading_, kSensorRangeM);
    const double ddiag = world().ray(pos_, heading_ + side_ * 0.25 * kPi, kSensorRangeM);
    double turn = 0.0;
    double advance = kStepM;
    if (mode_ == Mode::kPivot) {
      // Turning into a door on the searching hand, on the spot.
      const double step = std::min(15.0 * kDeg, pivot_left_);
      turn = side_ * step;
      pivot_left_ -= step;
      advance = 0.0;
      if (pivot_left_ <= 1e-9) {
        mode_ = Mode::kThrough;
        lost_m_ = 0.0;
      }
    } else if (mode_ == Mode::kThrough) {
      // Straight through the door, then follow whatever wall the room offers.
      if (lost_m_ > offset_ + 0.3) mode_ = Mode::kLost;
      lost_m_ += advance;
      lost_turn_ = 0.0;
    } else if (dfront < offset_ + 0.2 || ddiag < 1.1 * offset_) {
      // Wall ahead (an inside corner, furniture): turn away from the searching hand.
      turn = -side_ * 10.0 * kDeg;
      advance = dfront < offset_ + 0.2 ? 0.0 : 0.5 * kStepM;
      mode_ = Mode::kFollow;
    } else if (mode_ == Mode::kDoor) {
      // Walking to the middle of a door on the searching hand.
      door_left_ -= advance;
      if (door_left_ <= 0.0) {
        mode_ = Mode::kPivot;
        pivot_left_ = 0.5 * kPi;
        advance = 0.0;
      }
    } else if (dside > offset_ + 0.7) {
      if (mode_ == Mode::kFollow) {
        lost_m_ = 0.0;
        lost_turn_ = 0.0;
        const double width = opening_ahead();
        if (chance(config_.skip_room_probability)) {
          mode_ = Mode::kSkip;
        } else if (width > 0.0) {
          mode_ = Mode::kDoor;  // a door: walk to its middle, turn in
          door_left_ = 0.5 * width;
        } else {
          mode_ = Mode::kLost;  // the end of a wall or a wide opening: round it
        }
      }
      if (mode_ == Mode::kSkip) {
        if (lost_m_ > 3.0) mode_ = Mode::kLost;  // no wall came back: follow round after all
      } else if (mode_ == Mode::kLost && lost_m_ > offset_ + 0.1) {
        // Past the end of the wall: round it, towards the searching hand.
        turn = side_ * 8.0 * kDeg;
        lost_turn_ += 8.0;
        if (lost_turn_ > 400.0) {  // open space all round: head for the farthest free direction
          heading_ = freest_heading();
          lost_turn_ = 0.0;
          turn = 0.0;
        }
      }
      lost_m_ += advance;
    } else {
      mode_ = Mode::kFollow;
      // Steer to hold the offset from the followed wall.
      turn = std::clamp(side_ * 20.0 * kDeg * (dside - offset_), -6.0 * kDeg, 6.0 * kDeg);
    }
    heading_ = wrap_angle(heading_ + turn);
    turned_ += std::abs(turn);
    if (advance > 0.0) {
      const Vec2 next = pos_ + advance * dir(heading_);
      if (world().crosses(pos_, next) || world().clearance(next) < kMinClearanceM) {
        heading_ = wrap_angle(heading_ - side_ * 10.0 * kDeg);
        turned_ += 10.0 * kDeg;
        advance = 0.0;
        if (mode_ != Mode::kFollow) mode_ = Mode::kLost;
      } else {
        pos_ = next;
        moved_ += advance;
        since_offset_ += advance;
        on_stairs();
      }
    }
    if (since_offset_ > 4.0 && mode_ == Mode::kFollow) {
      offset_ = draw_offset();
      since_offset_ = 0.0;
    }
    const double stride = crawl_left_m_ > 0.0 ? config_.crawl_stride_m : config_.stride_m;
    if (moved_ >= stride || (turned_ > 40.0 * kDeg)) step(advance);
  }

  // Width of a door-like gap on the searching hand starting here: how far ahead the wall
  // comes back (0 when it does not within 2 m: the end of a wall, a corridor).
  double opening_ahead() const {
    for (double s = kStepM; s <= 2.0; s += kStepM) {
      const Vec2 ahead = pos_ + s * dir(heading_);
      if (world().crosses(pos_, ahead)) return 0.0;
      if (world().ray(ahead, heading_ + side_ * 0.5 * kPi, kSensorRangeM) < offset_ + 0.7) return s;
    }
    return 0.0;
  }

  double freest_heading() const {
    double best = heading_, best_range = -1.0;
    for (int k = 0; k < 16; ++k) {
      const double h = k * kPi / 8.0;
      const double r = world().ray(pos_, h, 10.0);
      if (r > best_range) {
        best_range = r;
        best = h;
      }
    }
    return best;
  }

  void on_stairs() {
    stair_rise_ = 0.0;
    for (const Stairs* s : plan_.stairs_of(floor_)) {
      const auto progress = s->progress(pos_);
      if (!progress) continue;
      const std::size_t lower = plan_.floor_index(s->lower_floor), upper = plan_.floor_index(s->upper_floor);
      const double rise = plan_.floors[upper].elevation_m - plan_.floors[lower].elevation_m;
      if (floor_ == lower && *progress > 0.5) floor_ = upper;
      if (floor_ == upper && *progress < 0.5) floor_ = lower;
      stair_rise_ = floor_ == lower ? *progress * rise : (*progress - 1.0) * rise;
      return;
    }
  }

  // A footfall where the walker stands now, after a swing whose duration follows the speed.
  void step(double /*last_advance*/) {
    const bool crawling = crawl_left_m_ > 0.0;
    const double speed = crawling ? config_.crawl_speed_mps : speed_;
    const double stride = crawling ? config_.crawl_stride_m : config_.stride_m;
    const double cycle = std::max(moved_, 0.3 * stride) / speed;
    // Crawling drags the boot forward quickly when the knee moves, then rests on it.
    const double stance_fraction = crawling ? kCrawlStanceFraction : config_.stance_fraction;
    Footfall f;
    f.t_land = lift_off() + std::max(0.25, (1.0 - stance_fraction) * cycle);
    f.stance_s = stance_fraction * cycle;
    f.position = Eigen::Vector3d(pos_.x(), pos_.y(), height());
    f.yaw = heading_;
    f.floor = floor_;
    f.gait = crawling ? Gait::kCrawl : Gait::kWalk;
    feet_.back().gait = f.gait;
    const double walked = moved_;
    moved_ = 0.0;
    turned_ = 0.0;
    crawl_left_m_ = std::max(0.0, crawl_left_m_ - walked);
    // Events, at their rates per metre walked.
    if (chance(config_.sweep_per_m * walked)) f.stance_s += uniform(1.0, 3.0);
    if (chance(config_.stop_per_m * walked)) f.stance_s += uniform(3.0, 10.0);
    if (!crawling && chance(config_.crawl_per_m * walked)) crawl_left_m_ = uniform(2.0, 5.0);
    feet_.push_back(f);
    time_ = lift_off();
    if (chance(config_.turn_back_per_m * walked)) turn_back(uniform(1.0, 3.0));
  }

  // Walk back over the last `metres` of footfalls and turn again: the path is retraced, so it
  // never crosses a wall.
  void turn_back(double metres) {
    std::vector<Footfall> back;
    double d = 0.0;
    for (std::size_t k = feet_.size() - 1; k > 1 && d < metres; --k) {
      d += (feet_[k].position - feet_[k - 1].position).head<2>().norm();
      back.push_back(feet_[k - 1]);
      if (feet_[k - 1].floor != floor_) break;
    }
    if (back.empty()) return;
    const Footfall here = feet_.back();
    auto append = [&](Eigen::Vector3d p, double yaw, std::size_t floor) {
      const double dist = (p - feet_.back().position).head<2>().norm();
      const double cycle = std::max(dist, 0.3 * config_.stride_m) / speed_;
      Footfall f;
      f.t_land = lift_off() + std::max(0.25, (1.0 - config_.stance_fraction) * cycle);
      f.stance_s = config_.stance_fraction * cycle;
      f.position = p;
      f.yaw = yaw;
      f.floor = floor;
      feet_.push_back(f);
    };
    append(here.position, wrap_angle(here.yaw + 0.5 * kPi), here.floor);  // pivot in two
    append(here.position, wrap_angle(here.yaw + kPi), here.floor);
    for (const Footfall& b : back) append(b.position, wrap_angle(b.yaw + kPi), b.floor);
    append(back.back().position, wrap_angle(back.back().yaw + 0.5 * kPi), back.back().floor);
    append(back.back().position, back.back().yaw, back.back().floor);
    for (auto it = back.rbegin() + 1; it != back.rend(); ++it) append(it->position, it->yaw, it->floor);
    append(here.position, here.yaw, here.floor);
    time_ = lift_off();
  }

  // The second member: the leader's footfalls, `follower_delay_s` later, a few cm off.
  std::vector<Footfall> follow(const std::vector<Footfall>& leader) {
    std::vector<Footfall> out = leader;
    std::normal_distribution<double> jitter(0.0, 0.03);
    for (std::size_t k = 0; k < out.size(); ++k) {
      if (k == 0) {
        out[k].stance_s += config_.follower_delay_s;
        continue;
      }
      out[k].t_land += config_.follower_delay_s;
      const Vec2 moved = out[k].position.head<2>() + Vec2(jitter(rng_), jitter(rng_));
      if (!world_[out[k].floor]->crosses(leader[k].position.head<2>(), moved)) out[k].position.head<2>() = moved;
    }
    return out;
  }

  enum class Mode { kFollow, kLost, kSkip, kDoor, kPivot, kThrough };

  const FloorPlan& plan_;
  SearchWalkConfig config_;
  Hand hand_;
  double side_;  ///< -1 right-hand, +1 left-hand: the followed wall's side
  std::mt19937_64& rng_;
  std::vector<std::unique_ptr<WallIndex>> world_;
  std::vector<Footfall> feet_;
  std::size_t floor_ = 0;
  Vec2 pos_ = Vec2::Zero();
  double heading_ = 0.0, speed_ = 0.4, offset_ = 0.5, stair_rise_ = 0.0;
  double time_ = 0.0, moved_ = 0.0, turned_ = 0.0, since_offset_ = 0.0;
  double lost_m_ = 0.0, lost_turn_ = 0.0, crawl_left_m_ = 0.0, door_left_ = 0.0, pivot_left_ = 0.0;
  Mode mode_ = Mode::kFollow;
};

}  // namespace

const char* to_string(Hand hand) { return hand == Hand::kRight ? "right" : "left"; }

void SearchWalkConfig::validate() const {
  auto check = [](const char* key, double v, double lo, double hi) { check_range("walk", key, v, lo, hi); };
  check("duration_s", duration_s, 10.0, 7200.0);
  check("standing_s", standing_s, 1.0, 600.0);
  check("speed_min_mps", speed_min_mps, 0.05, 2.0);
  check("speed_max_mps", speed_max_mps, speed_min_mps, 2.0);
  check("crawl_speed_mps", crawl_speed_mps, 0.02, 1.0);
  check("stride_m", stride_m, 0.2, 2.0);
  check("crawl_stride_m", crawl_stride_m, 0.1, 1.0);
  check("stance_fraction", stance_fraction, 0.2, 0.8);
  check("offset_min_m", offset_min_m, 0.2, 2.0);
  check("offset_max_m", offset_max_m, offset_min_m, 2.0);
  check("stop_per_m", stop_per_m, 0.0, 1.0);
  check("sweep_per_m", sweep_per_m, 0.0, 1.0);
  check("turn_back_per_m", turn_back_per_m, 0.0, 1.0);
  check("crawl_per_m", crawl_per_m, 0.0, 1.0);
  check("skip_room_probability", skip_room_probability, 0.0, 1.0);
  check("follower_delay_s", follower_delay_s, 0.0, 30.0);
}

SearchWalk generate_search_walk(const FloorPlan& plan, const SearchWalkConfig& config, Hand hand,
                                std::mt19937_64& rng) {
  config.validate();
  if (plan.entries.empty()) throw ConfigError("entries: the plan has no entry to start a search from");
  const Entry& entry = plan.entries[std::uniform_int_distribution<std::size_t>(0, plan.entries.size() - 1)(rng)];
  return generate_search_walk(plan, config, hand, entry.id, rng);
}

SearchWalk generate_search_walk(const FloorPlan& plan, const SearchWalkConfig& config, Hand hand,
                                const std::string& entry_id, std::mt19937_64& rng) {
  config.validate();
  const auto entry = std::find_if(plan.entries.begin(), plan.entries.end(), [&](const Entry& e) { return e.id == entry_id; });
  if (entry == plan.entries.end()) throw ConfigError("entry = '" + entry_id + "': not an entry of the plan");
  Walker walker(plan, config, hand, rng);
  SearchWalk walk = walker.run(*entry);
  walk.hand = hand;
  return walk;
}

double stance_heading(const Entry& entry, Hand hand) {
  // The door's wall is then on the searching hand.
  return entry.heading_rad + (hand == Hand::kRight ? -0.5 : 0.5) * kPi;
}

std::optional<EntryStance> entry_stance(const FloorPlan& plan, const std::string& entry_id, Hand hand) {
  for (const auto& e : plan.entries) {
    if (e.id == entry_id) return EntryStance{e.position, plan.floor_index(e.floor), stance_heading(e, hand)};
  }
  return std::nullopt;
}

double path_length(const std::vector<Footfall>& footfalls) {
  double d = 0.0;
  for (std::size_t k = 1; k < footfalls.size(); ++k) {
    d += (footfalls[k].position - footfalls[k - 1].position).head<2>().norm();
  }
  return d;
}

}  // namespace sarloc::firefighter
