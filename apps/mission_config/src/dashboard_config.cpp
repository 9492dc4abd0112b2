#include "sarloc/app/dashboard_config.hpp"

#include <cmath>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/identifier.hpp"

namespace sarloc::app {

namespace {

void check(bool ok, const std::string& key, const std::string& value, const std::string& rule) {
  if (!ok) throw ConfigError("dashboard." + key + " = " + value + ": " + rule);
}

bool within(double v, double low, double high) { return std::isfinite(v) && v >= low && v <= high; }

}  // namespace

void DashboardConfig::validate() const {
  check(!bind_address.empty(), "bind_address", "''", "must name an address (127.0.0.1, 0.0.0.0, ...)");
  check(port >= 0 && port <= 65535, "port", std::to_string(port), "must be 0-65535");
  check(token.empty() || token.size() >= 8, "token", "(hidden)", "must be at least 8 characters, or absent (a random one)");
  check(view_token.empty() || view_token.size() >= 8, "view_token", "(hidden)", "must be at least 8 characters, or absent (a random one)");
  check(view_token.empty() || view_token != token, "view_token", "(hidden)", "must differ from dashboard.token (viewers must not act)");
  if (auto problem = identifier_problem(operator_id, "dashboard.operator_id"); !problem.empty()) throw ConfigError(problem);
  check(within(stale_after_s, 0.5, 3600), "stale_after_s", std::to_string(stale_after_s), "must be in [0.5, 3600]");
  check(within(par_interval_s, 10, 86400), "par_interval_s", std::to_string(par_interval_s), "must be in [10, 86400]");
  check(within(push_period_s, 0.05, 10), "push_period_s", std::to_string(push_period_s), "must be in [0.05, 10]");
  check(max_streams >= 1 && max_streams <= 1000, "max_streams", std::to_string(max_streams), "must be 1-1000");
  check(max_connections_per_address >= 1 && max_connections_per_address <= 1000, "max_connections_per_address",
        std::to_string(max_connections_per_address), "must be 1-1000");
  check(within(request_deadline_s, 1, 120), "request_deadline_s", std::to_string(request_deadline_s), "must be in [1, 120]");
  check(foxglove_port >= -1 && foxglove_port <= 65535, "foxglove_port", std::to_string(foxglove_port), "must be -1 (off) or 0-65535");
  for (const auto& origin : feed_origins) {
    // An origin is scheme://host[:port], nothing more: what a browser sends, compared exactly.
    const bool ok = (origin.rfind("http://", 0) == 0 || origin.rfind("https://", 0) == 0) && origin.back() != '/' &&
                    origin.find_first_of(" \t\r\n") == std::string::npos && origin.size() <= 200;
    check(ok, "feed_origins", printable_excerpt(origin), "must be an origin as browsers send it (https://app.foxglove.dev)");
  }
  check(track_length >= 1 && track_length <= 10000, "track_length", std::to_string(track_length), "must be 1-10000");
}

}  // namespace sarloc::app
