#pragma once
// The Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1, foxglove/ws-protocol
// docs/spec.md) on sarloc's topics, so that Foxglove and Lichtblick show sarloc live with no
// plug-in: every topic advertised with its omgidl schema, and each subscribed channel's CDR
// payloads forwarded as they arrive (binary opcode 0x01: subscription id, timestamp, payload).
// Debian's websocketpp on asio, over TCP or TLS; its own thread and port.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "session_store.hpp"
#include "tls_context.hpp"

namespace sarloc::dashboard {

struct FoxgloveChannel {
  std::uint32_t id = 0;
  std::string topic;        ///< "sarloc/odometry"
  std::string schema_name;  ///< "sarloc::Odometry"
  std::string schema;       ///< the self-contained IDL text
};

/// What the feed lets a client do. Nothing a client sends may stop the process, and no client
/// may make it queue without limit (issue 59: "[]" as a text frame ended the dashboard; 5000
/// subscriptions of a client that stopped reading took it from 52 to 431 MB in 6 s).
struct FoxgloveBridgeConfig {
  std::string bind_address = "127.0.0.1";
  int port = 8765;  ///< 0: any free port
  /// Browsers send an Origin; any web page the commander opens could otherwise connect and read
  /// every topic. A client that sends one must be on this list ("https://app.foxglove.dev" for
  /// Foxglove's web app); clients that send none (desktop viewers, tools) are let in.
  std::vector<std::string> allowed_origins;
  std::size_t max_clients = 16;
  std::size_t max_subscriptions_per_client = 64;  ///< 13 topics: room to spare
  /// A client whose unsent frames exceed this is too slow: it is dropped, not queued for.
  std::size_t max_queued_bytes = 4u << 20;
  std::size_t max_message_bytes = 64u << 10;  ///< a client's largest frame (a subscribe list)
  /// The page's credentials: a client needs the view or operator token as the URL's query
  /// (ws://HOST:PORT/?token=T, which Foxglove and Lichtblick keep), or the page's session
  /// cookie. Null: anyone (tests of the protocol alone).
  std::shared_ptr<const SessionStore> access;
  /// The feed over TLS (wss://): a PEM certificate chain and its key, both or neither, and with
  /// a client authority only clients showing its certificate; the dashboard passes its own
  /// (dashboard.tls_certificate, tls_private_key, tls_client_ca).
  TlsFiles tls;
};

class FoxgloveBridge {
 public:
  FoxgloveBridge(FoxgloveBridgeConfig config, std::vector<FoxgloveChannel> channels);
  ~FoxgloveBridge();
  FoxgloveBridge(const FoxgloveBridge&) = delete;
  FoxgloveBridge& operator=(const FoxgloveBridge&) = delete;

  /// Listens (throws std::runtime_error naming the address) and serves on its own thread.
  void start();
  void stop();
  int port() const { return port_; }
  std::size_t clients() const;
  /// Clients dropped for queuing more than max_queued_bytes, since start.
  std::size_t slow_clients_dropped() const;

  /// Forwards one payload of channel `channel_id` to every client subscribed to it.
  void publish(std::uint32_t channel_id, std::uint64_t timestamp_ns, const std::uint8_t* data, std::size_t size);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
};

}  // namespace sarloc::dashboard
