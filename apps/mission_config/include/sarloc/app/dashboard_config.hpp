#pragma once
// The mission file's dashboard: section (sarloc-dashboard), validated at load.
#include <string>
#include <vector>

namespace sarloc::app {

struct DashboardConfig {
  std::string bind_address = "127.0.0.1";  ///< loopback only unless the file says otherwise
  int port = 8080;                         ///< 0: any free port (tests)
  /// Every operator action needs it (Authorization: Bearer TOKEN). Empty here: sarloc-dashboard
  /// makes a random one at start and logs it; --token or SARLOC_DASHBOARD_TOKEN set it too.
  std::string token;
  /// Looking at the picture (the page's data, the event stream, the Foxglove feed) needs this
  /// token, the operator token, or a session opened with either. Empty here: --view-token,
  /// SARLOC_DASHBOARD_VIEW_TOKEN, or a random one made at start.
  std::string view_token;
  std::string operator_id = "dashboard";  ///< who acknowledges alarms, as published over DDS
  double stale_after_s = 5.0;             ///< the "no data" banner after this long without a sample (wall s)
  double par_interval_s = 600.0;          ///< a team's PAR is due this long after the last (wall s)
  double push_period_s = 0.25;            ///< an event stream sends what changed at most this often
  int max_streams = 64;                   ///< open event streams at once
  /// Open connections to the page from one client address; more are closed at once (a
  /// browser opens about 7). One client can no longer hold every server thread (issue 59).
  int max_connections_per_address = 32;
  /// A connection's whole request must arrive within this (wall s) of its opening, or it is
  /// closed: against clients that send a byte every few seconds.
  double request_deadline_s = 10.0;
  int track_length = 120;                 ///< recent positions drawn per responder
  /// The Foxglove WebSocket feed (foxglove.websocket.v1) on this port of bind_address; -1: off,
  /// 0: any free port.
  int foxglove_port = 8765;
  /// Web origins whose pages may open the feed (a browser sends its page's origin; any other
  /// page the commander opens could read every topic). Clients sending no Origin (desktop
  /// viewers, tools) are let in. Foxglove's web app: "https://app.foxglove.dev".
  std::vector<std::string> feed_origins;
  /// The page over TLS (HTTPS): a PEM certificate and its key, both or neither
  /// (deploy/security/make-dashboard-cert.sh). Any bind_address but loopback needs them.
  std::string tls_certificate;
  std::string tls_private_key;
  /// With TLS: only clients showing a certificate this authority (PEM) signed are served, the page
  /// and the feed alike (mutual TLS: deploy/security/make-dashboard-client.sh issues an operator
  /// laptop's). Empty: any client that has a token. Relative to the mission file.
  std::string tls_client_ca;
  /// Names and addresses the page is reached by, beyond loopback and a specific bind_address;
  /// required with bind_address 0.0.0.0. Any other Host gets 421 (DNS rebinding).
  std::vector<std::string> hosts;
  /// An offline raster basemap under the map: an MBTiles file of PNG or JPEG tiles (relative to
  /// the mission file). Empty: none, the map as before.
  std::string basemap;

  /// Throws ConfigError naming the key, the value and the rule ("dashboard.port = ...").
  void validate() const;
};

}  // namespace sarloc::app
