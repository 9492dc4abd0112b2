#include "connection_gate.hpp"

#include <openssl/ssl.h>
#include <spdlog/spdlog.h>

#include <array>
#include <cctype>
#include <charconv>
#include <optional>
#include <stdexcept>
#include <vector>

namespace sarloc::dashboard {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

namespace {

// The value of the head's Content-Length, nullopt without one (or with one that is not a
// number: the server refuses that, so it may have it at once, as a head without a body).
std::optional<std::size_t> content_length(std::string_view head) {
  constexpr std::string_view kName = "content-length:";
  for (std::size_t line = head.find('\n'); line != std::string_view::npos; line = head.find('\n', line + 1)) {
    const std::string_view rest = head.substr(line + 1);
    if (rest.size() < kName.size()) break;
    bool match = true;
    for (std::size_t i = 0; i < kName.size() && match; ++i) {
      match = std::tolower(static_cast<unsigned char>(rest[i])) == kName[i];
    }
    if (!match) continue;
    std::size_t i = kName.size();
    while (i < rest.size() && (rest[i] == ' ' || rest[i] == '\t')) ++i;
    std::size_t value = 0;
    const auto [end, error] = std::from_chars(rest.data() + i, rest.data() + rest.size(), value);
    if (error != std::errc() || end == rest.data() + i) return std::nullopt;
    return value;
  }
  return std::nullopt;
}

}  // namespace

bool request_ready(std::string_view held) {
  if (held.empty()) return false;
  if (static_cast<unsigned char>(held.front()) == 0x16) return true;  // TLS: nothing to read here
  if (held.size() > kHeldRequestMax) return true;                     // for the server to refuse
  std::size_t head_end = held.find("\r\n\r\n");
  head_end = head_end == std::string_view::npos ? held.find("\n\n") : head_end;
  if (head_end == std::string_view::npos) return false;
  const std::string_view head = held.substr(0, head_end);
  const std::size_t body_start = head_end + (held.compare(head_end, 4, "\r\n\r\n") == 0 ? 4 : 2);
  const std::optional<std::size_t> length = content_length(head);
  // A body over the server's limit is refused on its head: no need to wait for it.
  if (!length || *length > kMaxRequestBody) return true;
  return held.size() - body_start >= *length;
}

// One client connection and its copy towards the HTTP server. Its sockets and flags belong to
// the gate's io thread; `deadline` and `served` are shared with the server's threads under the
// gate's mutex.
struct ConnectionGate::Relay {
  explicit Relay(tcp::socket socket) : client(std::move(socket)), backend(client.get_executor()) {}
  /// The client's bytes, decrypted when the gate ends its TLS.
  template <class Handler>
  void read_client(asio::mutable_buffer buffer, Handler&& handler) {
    if (tls) {
      tls->async_read_some(buffer, std::forward<Handler>(handler));
    } else {
      client.async_read_some(buffer, std::forward<Handler>(handler));
    }
  }
  template <class Handler>
  void write_client(asio::const_buffer buffer, Handler&& handler) {
    if (tls) {
      asio::async_write(*tls, buffer, std::forward<Handler>(handler));
    } else {
      asio::async_write(client, buffer, std::forward<Handler>(handler));
    }
  }
  tcp::socket client;
  std::unique_ptr<asio::ssl::stream<tcp::socket&>> tls;  // after `client`, which it uses
  tcp::socket backend;
  std::array<char, 16384> upstream_buffer{};    // client -> server
  std::array<char, 16384> downstream_buffer{};  // server -> client
  std::string held;                             // what the client sent before its request head was whole
  std::string address;
  int relay_port = 0;  // the local port of `backend`: how the server names this connection
  Clock::time_point deadline;
  bool holding = true;  // its request not yet whole: nothing of it has reached the server
  bool certified = false;  // its client showed a certificate of the context's client authority
  bool served = false;
  bool closed = false;
};

ConnectionGate::ConnectionGate(ConnectionLimits limits, const std::string& bind_address, int port, int backend_port,
                               std::shared_ptr<asio::ssl::context> tls)
    : limits_(limits),
      tls_(std::move(tls)),
      backend_port_(backend_port),
      acceptor_(io_),
      sweep_timer_(io_),
      accept_backoff_(io_) {
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(bind_address, ec);
  if (ec) throw std::runtime_error("cannot listen on '" + bind_address + "': not an IP address");
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(port));
  acceptor_.open(endpoint.protocol(), ec);
  if (!ec) acceptor_.set_option(tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor_.bind(endpoint, ec);
  if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    throw std::runtime_error("cannot listen on " + bind_address + ":" + std::to_string(port) + " (" + ec.message() + ")");
  }
  port_ = acceptor_.local_endpoint().port();
  accept();
  sweep();
  thread_ = std::thread([this] { io_.run(); });
}

ConnectionGate::~ConnectionGate() { stop(); }

void ConnectionGate::stop() {
  if (!thread_.joinable()) return;
  // Closing everything leaves the io thread no work: run() returns.
  asio::post(io_, [this] {
    stopping_ = true;  // a sweep already due must not arm the timer again
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    sweep_timer_.cancel();
    accept_backoff_.cancel();
    std::set<std::shared_ptr<Relay>> open;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      open = relays_;
    }
    for (const auto& relay : open) close(relay);
  });
  if (thread_.joinable()) thread_.join();
}

void ConnectionGate::request_arrived(int relay_port) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = by_relay_port_.find(relay_port);
  if (it != by_relay_port_.end()) it->second->served = true;
}

ConnectionGate::Counters ConnectionGate::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

void ConnectionGate::accept() {
  acceptor_.async_accept([this](const boost::system::error_code& ec, tcp::socket socket) {
    if (!acceptor_.is_open() || stopping_) return;
    if (!ec) {
      admit(std::move(socket));
      accept();
      return;
    }
    // Out of file descriptors (or the like): accepting again at once would spin on the error.
    refusals_.warn("accept", ec.message(), "dashboard: cannot accept a connection: " + ec.message());
    accept_backoff_.expires_after(std::chrono::milliseconds(100));
    accept_backoff_.async_wait([this](const boost::system::error_code& error) {
      if (!error && !stopping_) accept();
    });
  });
}

void ConnectionGate::admit(tcp::socket socket) {
  boost::system::error_code ec;
  const auto remote = socket.remote_endpoint(ec);
  if (ec) return;  // gone already
  auto relay = std::make_shared<Relay>(std::move(socket));
  relay->address = remote.address().to_string();
  const char* refusal = nullptr;
  std::shared_ptr<Relay> evicted;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    int& open = open_per_address_[relay->address];
    if (open < limits_.max_per_address && static_cast<int>(relays_.size()) >= limits_.max_total) {
      evicted = to_evict();
    }
    if (open >= limits_.max_per_address) {
      ++counters_.refused_address;
      refusal = "connections from that address";
    } else if (static_cast<int>(relays_.size()) >= limits_.max_total && !evicted) {
      ++counters_.refused_total;
      refusal = "connections in all";
      if (open == 0) open_per_address_.erase(relay->address);
    } else {
      if (evicted) ++counters_.evicted;
      ++open;
      ++counters_.relayed;
      relays_.insert(relay);
      relay->deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(limits_.request_deadline_s));
    }
  }
  if (refusal != nullptr) {
    refusals_.warn(relay->address, refusal,
                   std::string("dashboard: refused a connection from ") + relay->address + ": too many open " + refusal);
    relay->client.close(ec);
    return;
  }
  if (evicted) {
    refusals_.warn(evicted->address, "evicted",
                   "dashboard: closed a connection from " + evicted->address +
                       ": every connection is open, and that address held the most unfinished requests");
    close(evicted);
  }
  if (tls_) {
    // The handshake too must end by the deadline (sweep), and the connection is held meanwhile.
    relay->tls = std::make_unique<asio::ssl::stream<tcp::socket&>>(relay->client, *tls_);
    relay->tls->async_handshake(asio::ssl::stream_base::server, [this, relay](const boost::system::error_code& error) {
      if (relay->closed) return;
      const bool certified = !error && SSL_get0_peer_certificate(relay->tls->native_handle()) != nullptr &&
                             SSL_get_verify_result(relay->tls->native_handle()) == X509_V_OK;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        relay->certified = certified;
        if (error) ++counters_.failed_handshakes;
        if (certified) ++counters_.certified;
      }
      if (error) {
        // Not TLS, not a version or cipher we speak, or no client certificate we accept.
        refusals_.warn(relay->address, "handshake",
                       "dashboard: TLS handshake from " + relay->address + " failed: " + error.message());
        close(relay);
        return;
      }
      hold(relay);
    });
    return;
  }
  hold(relay);
}

// Full: a connection without a whole request makes room, so that slow clients of many addresses
// cannot keep a newcomer out (a browser's request is whole within milliseconds of its
// connection); connections whose request reached the server stay, and so does an operator's
// certificate, whoever opens connections. Of the rest, the address holding the most unfinished
// connections gives up its oldest: a flood then closes its own connections, and a newcomer's
// (a commander's browser in its TLS handshake, or on a slow link) outlasts it unless the flood
// comes from about as many addresses as the gate holds unfinished connections, divided by the
// newcomer's own. Oldest alone, any flood faster than one handshake closed the commander's
// connection before it could show its certificate.
std::shared_ptr<ConnectionGate::Relay> ConnectionGate::to_evict() const {
  auto evictable = [](const std::shared_ptr<Relay>& r) { return r->holding && !r->closed && !r->certified; };
  std::map<std::string_view, int> held_per_address;
  for (const auto& r : relays_) {
    if (evictable(r)) ++held_per_address[r->address];
  }
  std::shared_ptr<Relay> evicted;
  int evicted_held = 0;
  for (const auto& r : relays_) {
    if (!evictable(r)) continue;
    const int held = held_per_address[r->address];
    if (!evicted || held > evicted_held || (held == evicted_held && r->deadline < evicted->deadline)) {
      evicted = r;
      evicted_held = held;
    }
  }
  return evicted;
}

// The request stays here, where a connection costs a socket and a buffer, until it has arrived
// whole (request_ready): only then does the connection take one of the server's threads.
void ConnectionGate::hold(const std::shared_ptr<Relay>& relay) {
  relay->read_client(asio::buffer(relay->upstream_buffer),
                     [this, relay](const boost::system::error_code& ec, std::size_t n) {
                       if (relay->closed) return;
                       if (ec) {
                         close(relay);
                         return;
                       }
                       relay->held.append(relay->upstream_buffer.data(), n);
                       if (request_ready(relay->held)) {
                         connect(relay);
                         return;
                       }
                       hold(relay);
                     });
}

void ConnectionGate::connect(const std::shared_ptr<Relay>& relay) {
  relay->holding = false;
  relay->backend.async_connect(tcp::endpoint(asio::ip::address_v4::loopback(), static_cast<unsigned short>(backend_port_)),
                               [this, relay](const boost::system::error_code& error) {
                                 if (error || relay->closed) {
                                   close(relay);
                                   return;
                                 }
                                 boost::system::error_code ignored;
                                 relay->relay_port = relay->backend.local_endpoint(ignored).port();
                                 {
                                   std::lock_guard<std::mutex> lock(mutex_);
                                   by_relay_port_[relay->relay_port] = relay;
                                 }
                                 asio::async_write(relay->backend, asio::buffer(relay->held),
                                                   [this, relay](const boost::system::error_code& e, std::size_t) {
                                                     if (e || relay->closed) {
                                                       close(relay);
                                                       return;
                                                     }
                                                     relay->held.clear();
                                                     relay->held.shrink_to_fit();
                                                     pump(relay, true);
                                                   });
                                 pump(relay, false);
                               });
}

void ConnectionGate::pump(const std::shared_ptr<Relay>& relay, bool upstream) {
  auto& buffer = upstream ? relay->upstream_buffer : relay->downstream_buffer;
  auto relayed = [this, relay, upstream](const boost::system::error_code& ec, std::size_t n) {
    if (relay->closed) return;
    // Either end ends the connection: the server answers one request per connection, and
    // answers no client that has shut its sending side (cpp-httplib), so a client's end is
    // its leaving; the server's stream then fails at its next write and frees its thread.
    if (ec) {
      close(relay);
      return;
    }
    auto written = [this, relay, upstream](const boost::system::error_code& error, std::size_t) {
      if (error) {
        close(relay);
        return;
      }
      pump(relay, upstream);
    };
    if (upstream) {
      asio::async_write(relay->backend, asio::buffer(relay->upstream_buffer.data(), n), written);
    } else {
      relay->write_client(asio::buffer(relay->downstream_buffer.data(), n), written);
    }
  };
  if (upstream) {
    relay->read_client(asio::buffer(buffer), relayed);
  } else {
    relay->backend.async_read_some(asio::buffer(buffer), relayed);
  }
}

void ConnectionGate::close(const std::shared_ptr<Relay>& relay) {
  if (relay->closed) return;
  relay->closed = true;
  boost::system::error_code ignored;
  relay->client.close(ignored);
  relay->backend.close(ignored);
  std::lock_guard<std::mutex> lock(mutex_);
  relays_.erase(relay);
  const auto by_port = by_relay_port_.find(relay->relay_port);
  if (by_port != by_relay_port_.end() && by_port->second == relay) by_relay_port_.erase(by_port);
  const auto open = open_per_address_.find(relay->address);
  if (open != open_per_address_.end() && --open->second <= 0) open_per_address_.erase(open);
}

void ConnectionGate::sweep() {
  sweep_timer_.expires_after(std::chrono::milliseconds(200));
  sweep_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || stopping_) return;
    std::vector<std::shared_ptr<Relay>> expired;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto now = Clock::now();
      for (const auto& relay : relays_) {
        if (!relay->served && now >= relay->deadline) expired.push_back(relay);
      }
      counters_.expired += expired.size();
    }
    for (const auto& relay : expired) {
      refusals_.warn(relay->address, "deadline",
                     fmt::format("dashboard: closed a connection from {}: no whole request within {:g} s", relay->address,
                                 limits_.request_deadline_s));
      close(relay);
    }
    sweep();
  });
}

}  // namespace sarloc::dashboard
