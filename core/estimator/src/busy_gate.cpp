#include "sarloc/core/estimator/busy_gate.hpp"

#include <utility>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::estimator {
namespace {

BusyGate::Clock::duration seconds(double s) {
  return std::chrono::duration_cast<BusyGate::Clock::duration>(std::chrono::duration<double>(s));
}

}  // namespace

void BusyGateConfig::validate() const {
  if (!(max_wait_s >= 0.0 && max_wait_s <= 10.0)) {
    throw ConfigError("core.busy_wait_s = " + config_value(max_wait_s) + ": must be in [0, 10]");
  }
  if (!(max_utilisation >= 0.0 && max_utilisation <= 1.0)) {
    throw ConfigError("core.busy_utilisation = " + config_value(max_utilisation) + ": must be in [0, 1]");
  }
  if (!(hold_s >= 0.0 && hold_s <= 600.0)) {
    throw ConfigError("core.busy_hold_s = " + config_value(hold_s) + ": must be in [0, 600]");
  }
  if (!(shed_wait_s >= 0.0 && shed_wait_s <= 60.0)) {
    throw ConfigError("core.busy_shed_wait_s = " + config_value(shed_wait_s) + ": must be in [0, 60] (0: never)");
  }
}

BusyGate::BusyGate(BusyGateConfig config)
    : config_((config.validate(), std::move(config))),
      max_wait_(seconds(config_.max_wait_s)),
      hold_(seconds(config_.hold_s)),
      busy_until_(Clock::time_point::min().time_since_epoch().count()),
      shed_at_(Clock::time_point::min().time_since_epoch().count()) {}

bool BusyGate::note_wait(Clock::duration wait, Clock::time_point now) {
  if (config_.max_wait_s <= 0.0 || wait <= max_wait_) return false;
  return hold_closed_from(now);
}

bool BusyGate::note_shed(Clock::duration wait, Clock::time_point now) {
  if (config_.shed_wait_s <= 0.0 || wait <= seconds(config_.shed_wait_s)) return false;
  // One a second: a release shows in the waits within that (its queued samples go with it).
  const Clock::rep now_rep = now.time_since_epoch().count();
  Clock::rep last = shed_at_.load();
  if (last != Clock::time_point::min().time_since_epoch().count() && now_rep - last < seconds(1.0).count())
    return false;
  return shed_at_.compare_exchange_strong(last, now_rep);  // two workers at once: one releases
}

bool BusyGate::note_utilisation(double share, Clock::time_point now) {
  if (config_.max_utilisation <= 0.0 || !(share > config_.max_utilisation)) return false;
  return hold_closed_from(now);
}

bool BusyGate::hold_closed_from(Clock::time_point now) {
  const Clock::rep until = (now + hold_).time_since_epoch().count();
  const Clock::rep now_rep = now.time_since_epoch().count();
  Clock::rep seen = busy_until_.load();
  // Only ever later: two workers noting at once keep the later end.
  while (seen < until && !busy_until_.compare_exchange_weak(seen, until)) {
  }
  if (seen >= now_rep) return false;  // closed already
  closings_.fetch_add(1);
  return true;
}

bool BusyGate::busy(Clock::time_point now) const { return now.time_since_epoch().count() < busy_until_.load(); }

}  // namespace sarloc::estimator
