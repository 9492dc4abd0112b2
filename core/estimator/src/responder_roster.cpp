#include "sarloc/core/estimator/responder_roster.hpp"

#include <algorithm>
#include <utility>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::estimator {

void ResponderRosterConfig::validate() const {
  if (max_responders < 1) throw ConfigError("core.max_rescuers = 0: must be >= 1");
  if (!(idle_evict_s >= 1.0 && idle_evict_s <= 86400.0)) {
    throw ConfigError("core.idle_evict_s = " + config_value(idle_evict_s) + ": must be in [1, 86400]");
  }
  if (!(new_per_s >= 0.0 && new_per_s <= 10000.0)) {
    throw ConfigError("core.new_rescuers_per_s = " + config_value(new_per_s) + ": must be in [0, 10000]");
  }
  for (const auto& id : listed) {
    if (id.empty()) throw ConfigError("core roster: a listed responder id is empty");
  }
  for (const auto& id : door_starts) {
    if (id.empty()) throw ConfigError("core roster: a firefighter id with a reported entry is empty");
  }
}

ResponderRoster::ResponderRoster(ResponderRosterConfig config)
    : config_((config.validate(), std::move(config))),
      listed_(config_.listed.begin(), config_.listed.end()),
      door_starts_(config_.door_starts.begin(), config_.door_starts.end()),
      new_tokens_(std::max(1.0, config_.new_per_s)) {}

ResponderRoster::Admission ResponderRoster::admit(const std::string& id, Clock::time_point now, bool busy,
                                                  bool first_step) {
  if (id.empty()) return Admission::kEmptyId;
  if (auto it = served_.find(id); it != served_.end()) {
    it->second.last_heard = std::max(it->second.last_heard, now);
    return Admission::kServed;
  }
  if (!config_.open && listed_.count(id) == 0) return Admission::kNotListed;
  if (config_.open && served_.size() >= config_.max_responders) return Admission::kFull;
  if (first_step && door_starts_.erase(id) > 0) {
    // Once per daemon: a later "first step" (a device restarted, or a forged one) is no walk
    // from the door. Admitted 0th: released last (its filter is cheap, its entry not to be had again).
    served_.emplace(id, Served{now, 0});
    return Admission::kNew;
  }
  if (busy) return Admission::kBusy;
  if (config_.new_per_s > 0.0) {
    const double burst = std::max(1.0, config_.new_per_s);
    if (refilled_at_ && now > *refilled_at_) {
      new_tokens_ =
          std::min(burst, new_tokens_ + config_.new_per_s * std::chrono::duration<double>(now - *refilled_at_).count());
    }
    if (!refilled_at_ || now > *refilled_at_) refilled_at_ = now;
    if (new_tokens_ < 1.0) return Admission::kPaced;
    new_tokens_ -= 1.0;
  }
  served_.emplace(id, Served{now, ++admissions_});
  return Admission::kNew;
}

std::vector<std::string> ResponderRoster::evict_idle(Clock::time_point now) {
  const auto idle = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(config_.idle_evict_s));
  std::vector<std::pair<Clock::time_point, std::string>> gone;
  for (auto it = served_.begin(); it != served_.end();) {
    if (now - it->second.last_heard >= idle) {
      gone.emplace_back(it->second.last_heard, it->first);
      it = served_.erase(it);
    } else {
      ++it;
    }
  }
  std::sort(gone.begin(), gone.end());
  std::vector<std::string> ids;
  ids.reserve(gone.size());
  for (auto& [heard, id] : gone) ids.push_back(std::move(id));
  return ids;
}

std::optional<std::string> ResponderRoster::release_newest(const std::function<bool(const std::string&)>& among) {
  auto newest = served_.end();
  for (auto it = served_.begin(); it != served_.end(); ++it) {
    if ((!among || among(it->first)) && (newest == served_.end() || it->second.admitted > newest->second.admitted))
      newest = it;
  }
  if (newest == served_.end()) return std::nullopt;
  std::string id = newest->first;
  served_.erase(newest);
  return id;
}

bool refused(ResponderRoster::Admission a) {
  return a != ResponderRoster::Admission::kServed && a != ResponderRoster::Admission::kNew;
}

const char* reason_of(ResponderRoster::Admission a) {
  switch (a) {
    case ResponderRoster::Admission::kFull:
      return "too_many_rescuers";
    case ResponderRoster::Admission::kBusy:
      return "daemon_busy";
    case ResponderRoster::Admission::kPaced:
      return "admission_paced";
    case ResponderRoster::Admission::kEmptyId:
    case ResponderRoster::Admission::kNotListed:
      return "unknown_rescuer";
    default:
      return "";
  }
}

}  // namespace sarloc::estimator
