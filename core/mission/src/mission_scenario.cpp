#include "sarloc/core/mission/mission_scenario.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::mission {
namespace {

std::string fmt(const Vec3& v) {
  std::ostringstream os;
  os << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return os.str();
}

}  // namespace

void MissionScenario::validate() const {
  sensors.validate();
  if (victims.empty()) throw ConfigError("victims: at least one victim is needed");
  if (rescuers.empty()) throw ConfigError("rescuers: at least one rescuer is needed");
  for (std::size_t i = 0; i < victims.size(); ++i) {
    const auto& v = victims[i];
    const std::string key = "victims[" + std::to_string(i) + "]";
    if (!v.position.allFinite() || v.position.z() >= 0.0 || v.position.z() < -20.0) {
      throw ConfigError(key + ".position = " + fmt(v.position) + ": must be finite with z in [-20, 0) (buried)");
    }
    const double m = v.moment.norm();
    const double lo = sensors.standard.moment_min() * 0.999;
    const double hi = sensors.standard.moment_max() * 1.001;
    if (!v.moment.allFinite() || m < lo || m > hi) {
      std::ostringstream os;
      os << key << ".moment = " << fmt(v.moment) << ": |m| = " << m << " outside the standard's [" << lo << ", "
         << hi << "] A m^2";
      throw ConfigError(os.str());
    }
    const auto& rx = sensors.receiver;
    if (v.period_ms && !(*v.period_ms >= rx.period_min_ms && *v.period_ms <= rx.period_max_ms)) {
      std::ostringstream os;
      os << key << ".period_ms = " << *v.period_ms << ": outside the standard's [" << rx.period_min_ms << ", "
         << rx.period_max_ms << "] ms";
      throw ConfigError(os.str());
    }
    if (v.carrier_offset_hz && !(std::fabs(*v.carrier_offset_hz) <= rx.carrier_tolerance_hz)) {
      std::ostringstream os;
      os << key << ".carrier_offset_hz = " << *v.carrier_offset_hz << ": outside the standard's +-"
         << rx.carrier_tolerance_hz << " Hz";
      throw ConfigError(os.str());
    }
  }
  std::set<std::string> ids;
  for (std::size_t i = 0; i < rescuers.size(); ++i) {
    const auto& r = rescuers[i];
    const std::string key = "rescuers[" + std::to_string(i) + "]";
    if (r.id.empty() || r.id.size() > 64) throw ConfigError(key + ".id = '" + r.id + "': must be 1-64 characters");
    if (!ids.insert(r.id).second) throw ConfigError(key + ".id = '" + r.id + "': duplicate rescuer id");
    if (r.team.empty()) throw ConfigError(key + ".team is empty");
    if (!r.start.allFinite()) throw ConfigError(key + ".start = " + fmt(r.start) + ": must be finite");
    if (!std::isfinite(r.heading_deg)) throw ConfigError(key + ".heading_deg must be finite");
  }
  if (!(detection_range_m >= 10.0 && detection_range_m <= 150.0)) {
    throw ConfigError("simulation.detection_range_m = " + config_value(detection_range_m) + ": must be in [10, 150]");
  }
  if (!(gnss_sigma_m > 0.0 && gnss_sigma_m <= 50.0)) {
    throw ConfigError("simulation.gnss_sigma_m = " + config_value(gnss_sigma_m) + ": must be in (0, 50]");
  }
  if (!(gnss_correlation_s > 0.0 && gnss_correlation_s <= 3600.0)) {
    throw ConfigError("simulation.gnss_correlation_s = " + config_value(gnss_correlation_s) + ": must be in (0, 3600]");
  }
  if (!(gnss_white_sigma_m >= 0.0 && gnss_white_sigma_m <= 50.0)) {
    throw ConfigError("simulation.gnss_white_sigma_m = " + config_value(gnss_white_sigma_m) + ": must be in [0, 50]");
  }
  if (!(dig_out_after_s >= 0.0 && dig_out_after_s <= 3600.0)) {
    throw ConfigError("simulation.dig_out_after_s = " + config_value(dig_out_after_s) + ": must be in [0, 3600]");
  }
}

std::size_t MissionScenario::rescuer_index(const std::string& id) const {
  for (std::size_t i = 0; i < rescuers.size(); ++i) {
    if (rescuers[i].id == id) return i;
  }
  throw ConfigError("rescuer id '" + id + "' is not in the mission's rescuers");
}

}  // namespace sarloc::mission
