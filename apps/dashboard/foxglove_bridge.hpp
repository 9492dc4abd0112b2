#pragma once
// The Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1, foxglove/ws-protocol
// docs/spec.md) on sarloc's topics, so that Foxglove and Lichtblick show sarloc live with no
// plug-in: every topic advertised with its omgidl schema, and each subscribed channel's CDR
// payloads forwarded as they arrive (binary opcode 0x01: subscription id, timestamp, payload).
// Debian's websocketpp on asio; its own thread and port.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace sarloc::dashboard {

struct FoxgloveChannel {
  std::uint32_t id = 0;
  std::string topic;        ///< "sarloc/odometry"
  std::string schema_name;  ///< "sarloc::Odometry"
  std::string schema;       ///< the self-contained IDL text
};

class FoxgloveBridge {
 public:
  FoxgloveBridge(std::string bind_address, int port, std::vector<FoxgloveChannel> channels);
  ~FoxgloveBridge();
  FoxgloveBridge(const FoxgloveBridge&) = delete;
  FoxgloveBridge& operator=(const FoxgloveBridge&) = delete;

  /// Listens (throws std::runtime_error naming the address) and serves on its own thread.
  void start();
  void stop();
  int port() const { return port_; }
  std::size_t clients() const;

  /// Forwards one payload of channel `channel_id` to every client subscribed to it.
  void publish(std::uint32_t channel_id, std::uint64_t timestamp_ns, const std::uint8_t* data, std::size_t size);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string bind_address_;
  int port_ = 0;
};

}  // namespace sarloc::dashboard
