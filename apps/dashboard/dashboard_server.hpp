#pragma once
// sarloc-dashboard's HTTP side (Debian's cpp-httplib): the page and its assets, the picture as
// JSON, a server-sent event stream of changes, and the operator's actions (acknowledge an
// alarm, report a team's PAR, mark a victim dug out). Looking needs the view token (or the operator token, or a
// session opened with either); acting needs the operator token.
//
//   GET  /                      the page (index.html, app.js, style.css: no data, no external asset)
//   GET  /api/session           {"signed_in": bool, "may_act": bool} for this browser
//   POST /api/session           {"token": T}: a session cookie (HttpOnly, SameSite=Strict) for T
//   GET  /api/state             the whole picture (JSON)                       [view]
//   GET  /events                text/event-stream: "snapshot" once, then "delta" and "heartbeat" [view]
//   POST /api/alarms/ID/ack     acknowledge alarm ID   (Authorization: Bearer OPERATOR_TOKEN)
//   POST /api/teams/ID/par      a team's PAR reported  (Authorization: Bearer OPERATOR_TOKEN)
//   POST /api/victims/ID/dug-out  FOUND victim ID dug out (Authorization: Bearer OPERATOR_TOKEN;
//                               live only: 404 in a replay)
//   POST /api/victims/ID/dig-first  dig victim ID first, the rest of the order as shown
//                               (Authorization: Bearer OPERATOR_TOKEN; live only)
//   POST /api/replay            a replay's play, pause, seek [view; application/json only, so
//                               that no other site's form can post it]
// [view]: Authorization: Bearer VIEW_TOKEN (or the operator's), or the session cookie.
//
// Bad requests get a 4xx and a JSON {"error": ...}; nothing a client sends stops the server.
// Every request other than GET is judged on its head before its body is read: the token, its
// Origin (a browser's must be this server's own), no chunked body, at most 64 header fields.
// Every request names one of the server's hosts (DashboardServerConfig::hosts) or gets 421.
// Every response carries a Content-Security-Policy (default-src 'self'), X-Frame-Options DENY
// and nosniff.
#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "basemap.hpp"
#include "connection_gate.hpp"
#include "picture_state.hpp"
#include "session_store.hpp"

namespace httplib {
class Server;
class DataSink;
struct Request;
}

namespace sarloc::dashboard {

struct DashboardServerConfig {
  std::string bind_address = "127.0.0.1";  ///< all interfaces only when asked: 0.0.0.0
  int port = 8080;                         ///< 0: any free port (tests)
  std::string token;                       ///< the operator token: every action needs it; never empty when serving
  std::string view_token;                  ///< looking needs it (or the operator token); never empty when serving
  std::string operator_id = "dashboard";   ///< who acknowledges, as published over DDS
  double push_period_s = 0.25;             ///< a stream sends what changed at most this often
  int max_streams = 64;                    ///< open event streams at once; more get 503
  int max_connections_per_address = 32;    ///< ConnectionGate: open connections from one address
  double request_deadline_s = 10.0;        ///< ConnectionGate: a whole request within this of opening
  /// TLS: both PEM files, or neither. Without them the server binds loopback only (plain HTTP
  /// beyond this machine would carry the tokens in clear).
  std::string tls_certificate;
  std::string tls_private_key;
  /// With TLS: only clients showing a certificate this authority (PEM) signed are served, page and
  /// feed alike (mutual TLS; deploy/security/make-dashboard-client.sh). Empty: any client.
  std::string tls_client_ca;
  /// The names and addresses browsers reach the page by (the Host header, without its port).
  /// Loopback names and a specific bind_address are always in; a page reached by any other
  /// name gets 421, so that a site whose name was rebound to this address reads nothing.
  std::vector<std::string> hosts;

  /// Throws ConfigError naming the field, the value and the rule.
  void validate() const;
};

/// 127.x.x.x, ::1 or localhost.
bool is_loopback_address(const std::string& address);

class DashboardServer {
 public:
  /// `acknowledge(alarm_id, operator_id)` publishes the acknowledgement (false: DDS refused).
  DashboardServer(DashboardServerConfig config, PictureState& state,
                  std::function<bool(std::uint32_t, const std::string&)> acknowledge);
  ~DashboardServer();
  DashboardServer(const DashboardServer&) = delete;
  DashboardServer& operator=(const DashboardServer&) = delete;

  /// A replay's timeline (sarloc-dashboard --recording): POST /api/replay hands its JSON body
  /// to `control` and answers what it returns; std::invalid_argument becomes a 400. Set before
  /// start(). Without it, /api/replay is 404.
  void set_replay_control(std::function<nlohmann::json(const nlohmann::json&)> control);
  /// `dug_out(victim_id, operator_id)` publishes that a FOUND victim is dug out (false: DDS
  /// refused). Set before start(); without it (a replay), POST /api/victims/ID/dug-out is 404.
  void set_dug_out_action(std::function<bool(std::uint32_t, const std::string&)> dug_out);
  /// `dig_order(victim_ids, operator_id)` publishes an operator's dig order (false: DDS refused).
  /// Set before start(); without it, POST /api/victims/ID/dig-first is 404.
  void set_dig_order_action(std::function<bool(const std::vector<std::uint32_t>&, const std::string&)> dig_order);
  /// `deposit(outline, operator_id)` publishes an operator's outline of the deposit (incident
  /// frame; false: DDS refused). Set before start(); without it, POST /api/deposit is 404.
  void set_deposit_action(std::function<bool(const std::vector<Eigen::Vector2d>&, const std::string&)> deposit);
  /// The offline basemap's tiles, served as GET /api/basemap/Z/X/Y (the view token or a
  /// session). Set before start(); without it, those are 404.
  void set_basemap(std::shared_ptr<const app::Basemap> basemap) { basemap_ = std::move(basemap); }

  /// Binds (throws std::runtime_error naming the address when it cannot) and serves on a thread;
  /// returns once it listens. Once per server: std::logic_error after a start or a stop.
  void start();
  /// Ends every stream and the server; idempotent.
  void stop();
  int port() const { return port_; }
  /// What the gate in front of the server let in, refused and closed (after start()).
  ConnectionGate::Counters connection_counters() const { return gate_->counters(); }
  bool tls() const { return !config_.tls_certificate.empty(); }
  int open_streams() const { return streams_.load(); }
  /// The credentials this server accepts, for the Foxglove feed to accept the same.
  std::shared_ptr<const SessionStore> sessions() const { return sessions_; }

 private:
  /// The view or operator token as a Bearer, or an open session's cookie.
  bool may_view(const httplib::Request& request) const;
  /// The request's Host (its port removed) is one of this server's names.
  bool known_host(const std::string& host_header) const;
  /// One turn of an event stream: the first snapshot, or what changed, and a heartbeat each
  /// second. False ends the stream (the browser left, or the server stops).
  bool push_events(httplib::DataSink& sink, std::uint64_t& sent, std::chrono::steady_clock::time_point& beat);
  /// The event-stream message for a stream at version `since` (0: a first snapshot): made once
  /// per picture version and shared by every stream at the same point, so that 50 open pages
  /// cost one serialization, not 50.
  std::shared_ptr<const std::string> message_for(std::uint64_t since, bool first, std::uint64_t& version);

  DashboardServerConfig config_;
  PictureState& state_;
  std::function<bool(std::uint32_t, const std::string&)> acknowledge_;
  std::function<nlohmann::json(const nlohmann::json&)> replay_control_;
  std::function<bool(std::uint32_t, const std::string&)> dug_out_;
  std::function<bool(const std::vector<std::uint32_t>&, const std::string&)> dig_order_;
  std::function<bool(const std::vector<Eigen::Vector2d>&, const std::string&)> deposit_;
  std::shared_ptr<const app::Basemap> basemap_;
  std::shared_ptr<SessionStore> sessions_;
  std::unique_ptr<httplib::Server> server_;  ///< on a loopback port: clients reach it through gate_
  std::unique_ptr<ConnectionGate> gate_;     ///< the public port
  std::shared_ptr<boost::asio::ssl::context> tls_context_;  ///< the gate's TLS, when configured
  std::thread thread_;
  std::atomic<bool> listen_returned_{false};
  std::atomic<bool> stopping_{false};
  std::atomic<int> streams_{0};
  std::mutex cache_mutex_;
  struct Cached {
    std::uint64_t picture_version = 0;  // the picture it was made from
    std::uint64_t version = 0;          // the version it brings a stream to
    std::shared_ptr<const std::string> text;
  };
  std::map<std::pair<bool, std::uint64_t>, Cached> cache_;  // (first, since) -> message
  int port_ = 0;
};

}  // namespace sarloc::dashboard
