#pragma once
// The page's front door: every connection to the dashboard's port passes through here before
// cpp-httplib sees it.
//
// cpp-httplib 0.11 gives each connection a worker thread while it reads the request head, and
// restarts its 5 s read timeout on every byte: 80 clients sending a byte every 2 s held all 72
// threads, and 200 half-sent requests did the same for 16 s (issue 59). It offers no hook at
// accept. So the gate accepts on the public address itself and relays each connection to the
// HTTP server, which listens on a loopback port of its own; it
//  - holds each request until it has arrived whole (request_ready) before it connects to the
//    server: a connection being dribbled costs a socket and a buffer here, never a server
//    thread, so slow clients from any number of addresses cannot hold the server's threads;
//  - refuses a client address that already has `max_per_address` connections open;
//  - at `max_total` open connections, makes room for a new one by closing a connection whose
//    request has not arrived whole: the oldest of the address holding the most of them (counted
//    `evicted`); refuses it only when none may be closed (every request has reached the
//    server, or its client showed an operator's certificate);
//  - closes a connection whose request has not arrived whole within `request_deadline_s` of
//    its opening. The server reports a GET's head (request_arrived) by the port the relay's
//    connection comes from; the GET is then served as long as it lasts (event streams). A
//    request with a body is not reported: it must be answered by the deadline (4 KiB at most).
// With a TLS context the gate ends TLS itself (TLS 1.2 and up), and holds the decrypted
// request as above: a slow TLS client holds no server thread either (before 2026-12-05 TLS
// passed through to cpp-httplib's SSLServer, and a client that dribbled its request inside TLS
// held a server thread until the deadline). Without one, a TLS client passes at once (first
// byte 0x16) to the plain server, which refuses it. One request per connection (the server
// closes after each), so the deadline covers all of it, the TLS handshake included. With a
// client authority in the context (dashboard.tls_client_ca), only a client showing a certificate
// of that authority gets past the handshake, and its connection is never evicted to make room:
// anyone else on the network can cost the gate handshakes, but never reach the server, nor close
// an operator's connection once it has shown its certificate; during its handshake, only a flood
// from about as many addresses as the gate holds unfinished connections, divided by the
// operator's own, can (to_evict).
#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <thread>

#include "sarloc/dds/rate_limited_log.hpp"

namespace sarloc::dashboard {

/// Held longer than this without being whole, a request passes to the server, which refuses it.
inline constexpr std::size_t kHeldRequestMax = 16384;
/// The server's body limit: a larger Content-Length is refused on its head, so not waited for.
/// The largest body is a drawn deposit: 250 points as JSON, about 18 bytes each.
inline constexpr std::size_t kMaxRequestBody = 8192;

/// The bytes a client sent may go to the server: its request head has ended and the body its
/// Content-Length announces (at most kMaxRequestBody) has arrived, or it is TLS (first byte 0x16,
/// a handshake record: it cannot be read here), or it is over kHeldRequestMax.
bool request_ready(std::string_view held);

struct ConnectionLimits {
  int max_per_address = 32;         ///< open connections from one client address
  int max_total = 256;              ///< open connections in all
  double request_deadline_s = 10.0; ///< from opening to the request reaching its handler
};

class ConnectionGate {
 public:
  /// Listens on `bind_address`:`port` (0: any free port) and relays to 127.0.0.1:`backend_port`,
  /// ending TLS with `tls` when given (tls_context.hpp). Throws std::runtime_error when it cannot listen.
  ConnectionGate(ConnectionLimits limits, const std::string& bind_address, int port, int backend_port,
                 std::shared_ptr<boost::asio::ssl::context> tls = nullptr);
  ~ConnectionGate();
  ConnectionGate(const ConnectionGate&) = delete;
  ConnectionGate& operator=(const ConnectionGate&) = delete;

  int port() const { return port_; }
  /// Stops accepting and closes every open connection (then only request_arrived and
  /// counters may be called, harmlessly). The destructor does it too.
  void stop();
  /// Thread-safe (the server's handler threads): the GET on the connection that reaches the
  /// server from `relay_port` arrived whole; it has no deadline any more.
  void request_arrived(int relay_port);

  struct Counters {
    std::uint64_t relayed = 0;           ///< connections accepted and relayed
    std::uint64_t refused_address = 0;   ///< over max_per_address
    std::uint64_t refused_total = 0;     ///< over max_total, none of them held (all served)
    std::uint64_t evicted = 0;           ///< unfinished, closed at max_total for a new one (to_evict)
    std::uint64_t expired = 0;           ///< closed at request_deadline_s
    std::uint64_t failed_handshakes = 0;  ///< TLS not spoken, or no client certificate the context accepts
    std::uint64_t certified = 0;          ///< handshakes with a verified client certificate
  };
  Counters counters() const;

 private:
  struct Relay;
  using Clock = std::chrono::steady_clock;

  void accept();
  void admit(boost::asio::ip::tcp::socket socket);
  void sweep();
  /// On the io thread, under mutex_ (it reads the relays' io-thread flags): the connection to
  /// close for a newcomer when the gate is full, or null.
  std::shared_ptr<Relay> to_evict() const;
  void hold(const std::shared_ptr<Relay>& relay);
  void connect(const std::shared_ptr<Relay>& relay);
  void pump(const std::shared_ptr<Relay>& relay, bool upstream);
  void close(const std::shared_ptr<Relay>& relay);

  ConnectionLimits limits_;
  std::shared_ptr<boost::asio::ssl::context> tls_;  // null: plain HTTP
  int backend_port_ = 0;
  int port_ = 0;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer sweep_timer_;
  boost::asio::steady_timer accept_backoff_;  // after a failed accept
  bool stopping_ = false;  // the io thread's
  mutable std::mutex mutex_;
  std::set<std::shared_ptr<Relay>> relays_;
  std::map<std::string, int> open_per_address_;
  std::map<int, std::shared_ptr<Relay>> by_relay_port_;
  Counters counters_;
  dds::RateLimitedLog refusals_{std::chrono::seconds(10)};
  std::thread thread_;
};

}  // namespace sarloc::dashboard
