#pragma once
// sarloc-dashboard's HTTP side (Debian's cpp-httplib): the page and its assets, the picture as
// JSON, a server-sent event stream of changes, and the operator's actions (acknowledge an
// alarm, report a team's PAR), which need the access token.
//
//   GET  /                      the page (index.html, app.js, style.css: no external asset)
//   GET  /api/state             the whole picture (JSON)
//   GET  /events                text/event-stream: "snapshot" once, then "delta" and "heartbeat"
//   POST /api/alarms/ID/ack     acknowledge alarm ID   (Authorization: Bearer TOKEN)
//   POST /api/teams/ID/par      a team's PAR reported  (Authorization: Bearer TOKEN)
//   POST /api/replay            a replay's play, pause, seek (no token: it changes no incident;
//                               application/json only, so that no other site's form can post it)
//
// Bad requests get a 4xx and a JSON {"error": ...}; nothing a client sends stops the server.
// Every request other than GET is judged on its head before its body is read: the token, its
// Origin (a browser's must be this server's own), no chunked body, at most 64 header fields.
// Every response carries a Content-Security-Policy (default-src 'self'), X-Frame-Options DENY
// and nosniff.
#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <mutex>
#include <memory>
#include <string>
#include <thread>

#include "picture_state.hpp"

namespace httplib {
class Server;
class DataSink;
}

namespace sarloc::dashboard {

struct DashboardServerConfig {
  std::string bind_address = "127.0.0.1";  ///< all interfaces only when asked: 0.0.0.0
  int port = 8080;                         ///< 0: any free port (tests)
  std::string token;                       ///< required by every action; never empty when serving
  std::string operator_id = "dashboard";   ///< who acknowledges, as published over DDS
  double push_period_s = 0.25;             ///< a stream sends what changed at most this often
  int max_streams = 64;                    ///< open event streams at once; more get 503

  /// Throws ConfigError naming the field, the value and the rule.
  void validate() const;
};

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

  /// Binds (throws std::runtime_error naming the address when it cannot) and serves on a thread.
  void start();
  /// Ends every stream and the server; idempotent.
  void stop();
  int port() const { return port_; }
  int open_streams() const { return streams_.load(); }

 private:
  bool authorised(const std::string& header) const;
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
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
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

/// A random access token (128 bits, hex) for a dashboard started without one.
std::string random_token();

}  // namespace sarloc::dashboard
