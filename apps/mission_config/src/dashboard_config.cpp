#include "sarloc/app/dashboard_config.hpp"

#include <cmath>
#include <filesystem>

#include "sarloc/core/common/errors.hpp"
#include "sarloc/core/common/identifier.hpp"
#include "sarloc/core/common/validate.hpp"

namespace sarloc::app {

namespace {

// A secret never appears in a message.
void check_secret(bool ok, const std::string& key, const std::string& rule) {
  if (!ok) detail::throw_config_error("dashboard." + key, "(hidden)", rule);
}

bool within(double v, double low, double high) { return std::isfinite(v) && v >= low && v <= high; }

}  // namespace

void DashboardConfig::validate() const {
  require(!bind_address.empty(), "dashboard.bind_address", bind_address,
          "must name an address (127.0.0.1, 0.0.0.0, ...)");
  require(port >= 0 && port <= 65535, "dashboard.port", port, "must be 0-65535");
  check_secret(token.empty() || token.size() >= 8, "token", "must be at least 8 characters, or absent (a random one)");
  check_secret(view_token.empty() || view_token.size() >= 8, "view_token",
               "must be at least 8 characters, or absent (a random one)");
  check_secret(view_token.empty() || view_token != token, "view_token",
               "must differ from dashboard.token (viewers must not act)");
  if (auto problem = identifier_problem(operator_id, "dashboard.operator_id"); !problem.empty()) throw ConfigError(problem);
  require(within(stale_after_s, 0.5, 3600), "dashboard.stale_after_s", stale_after_s, "must be in [0.5, 3600]");
  require(within(par_interval_s, 10, 86400), "dashboard.par_interval_s", par_interval_s, "must be in [10, 86400]");
  require(within(push_period_s, 0.05, 10), "dashboard.push_period_s", push_period_s, "must be in [0.05, 10]");
  require(max_streams >= 1 && max_streams <= 1000, "dashboard.max_streams", max_streams, "must be 1-1000");
  require(max_connections_per_address >= 1 && max_connections_per_address <= 1000,
          "dashboard.max_connections_per_address", max_connections_per_address, "must be 1-1000");
  require(within(request_deadline_s, 1, 120), "dashboard.request_deadline_s", request_deadline_s,
          "must be in [1, 120]");
  require(foxglove_port >= -1 && foxglove_port <= 65535, "dashboard.foxglove_port", foxglove_port,
          "must be -1 (off) or 0-65535");
  for (const auto& origin : feed_origins) {
    // An origin is scheme://host[:port], nothing more: what a browser sends, compared exactly.
    const bool ok = (origin.rfind("http://", 0) == 0 || origin.rfind("https://", 0) == 0) && origin.back() != '/' &&
                    origin.find_first_of(" \t\r\n") == std::string::npos && origin.size() <= 200;
    if (!ok) {
      detail::throw_config_error("dashboard.feed_origins", printable_excerpt(origin),
                                 "must be an origin as browsers send it (https://app.foxglove.dev)");
    }
  }
  require(tls_client_ca.empty() || !tls_certificate.empty(), "dashboard.tls_client_ca", tls_client_ca,
          "client certificates are asked for in a TLS handshake: give dashboard.tls_certificate and "
          "tls_private_key too");
  // Opened (and its contents checked) by sarloc-dashboard; here only that it is there.
  std::error_code error;
  require(basemap.empty() || std::filesystem::is_regular_file(basemap, error), "dashboard.basemap", basemap,
          "must be an MBTiles file that exists (scripts/make-test-basemap makes one for trying)");
  require(track_length >= 1 && track_length <= 10000, "dashboard.track_length", track_length, "must be 1-10000");
}

}  // namespace sarloc::app
