#pragma once
// Test clients of the Foxglove feed (no DDS): a websocketpp client that records what arrives,
// and the frames a raw TCP client (raw_socket.hpp) sends after a handshake.
#include <websocketpp/client.hpp>
#include <websocketpp/config/asio_no_tls_client.hpp>

#include "raw_socket.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace sarloc::dashboard::test {

class FeedClient {
 public:
  using Client = websocketpp::client<websocketpp::config::asio_client>;

  /// Connects to ws://127.0.0.1:port`resource` with the Foxglove subprotocol; `origin` and
  /// `cookie` sent when not empty.
  FeedClient(int port, const std::string& origin = "", const std::string& resource = "/", const std::string& cookie = "") {
    client_.clear_access_channels(websocketpp::log::alevel::all);
    client_.clear_error_channels(websocketpp::log::elevel::all);
    client_.init_asio();
    client_.set_open_handler([this](websocketpp::connection_hdl) { set_state(kOpen); });
    client_.set_fail_handler([this](websocketpp::connection_hdl) { set_state(kClosed); });
    client_.set_close_handler([this](websocketpp::connection_hdl) { set_state(kClosed); });
    client_.set_message_handler([this](websocketpp::connection_hdl, Client::message_ptr m) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (m->get_opcode() == websocketpp::frame::opcode::text) {
        texts_.push_back(m->get_payload());
      } else {
        binaries_.push_back(m->get_payload());
      }
      cv_.notify_all();
    });
    websocketpp::lib::error_code ec;
    auto connection = client_.get_connection("ws://127.0.0.1:" + std::to_string(port) + resource, ec);
    if (ec) return;
    connection->add_subprotocol("foxglove.websocket.v1");
    if (!origin.empty()) connection->replace_header("Origin", origin);
    if (!cookie.empty()) connection->replace_header("Cookie", cookie);
    handle_ = connection->get_handle();
    client_.connect(connection);
    thread_ = std::thread([this] { client_.run(); });
  }
  ~FeedClient() {
    websocketpp::lib::error_code ignored;
    if (state() == kOpen) client_.close(handle_, websocketpp::close::status::normal, "", ignored);
    wait_for([this] { return state_ != kOpen; }, std::chrono::seconds(2));
    client_.stop();
    if (thread_.joinable()) thread_.join();
  }

  /// True once open; false when it failed or closed (within 5 s).
  bool opened() {
    wait_for([this] { return state_ != kConnecting; }, std::chrono::seconds(5));
    return state() == kOpen;
  }
  bool open() const { return state() == kOpen; }
  bool send_text(const std::string& text) {
    websocketpp::lib::error_code ec;
    client_.send(handle_, text, websocketpp::frame::opcode::text, ec);
    return !ec;
  }
  /// Waits until at least `count` text messages arrived (the first two: serverInfo, advertise).
  std::vector<std::string> texts(std::size_t count, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    wait_for([&] { return texts_.size() >= count; }, timeout);
    std::lock_guard<std::mutex> lock(mutex_);
    return texts_;
  }
  std::vector<std::string> binaries(std::size_t count, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    wait_for([&] { return binaries_.size() >= count; }, timeout);
    std::lock_guard<std::mutex> lock(mutex_);
    return binaries_;
  }

 private:
  enum State { kConnecting, kOpen, kClosed };
  State state() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_;
  }
  void set_state(State s) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_ = s;
    cv_.notify_all();
  }
  template <class Condition>
  void wait_for(Condition condition, std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, condition);
  }

  Client client_;
  websocketpp::connection_hdl handle_;
  std::thread thread_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  State state_ = kConnecting;
  std::vector<std::string> texts_;
  std::vector<std::string> binaries_;
};

/// The opening handshake a browser sends, with the Foxglove subprotocol.
inline std::string feed_handshake(const std::string& origin = "") {
  std::string request =
      "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
      "Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n";
  if (!origin.empty()) request += "Origin: " + origin + "\r\n";
  return request + "\r\n";
}

/// A client frame (masked, as RFC 6455 requires of clients) with any opcode and payload.
inline std::string client_frame(std::uint8_t opcode, const std::string& payload, bool fin = true) {
  std::string frame;
  frame += static_cast<char>((fin ? 0x80 : 0x00) | (opcode & 0x0F));
  const std::size_t n = payload.size();
  if (n < 126) {
    frame += static_cast<char>(0x80 | n);
  } else if (n <= 0xFFFF) {
    frame += static_cast<char>(0x80 | 126);
    frame += static_cast<char>(n >> 8);
    frame += static_cast<char>(n & 0xFF);
  } else {
    frame += static_cast<char>(0x80 | 127);
    for (int i = 7; i >= 0; --i) frame += static_cast<char>((static_cast<std::uint64_t>(n) >> (8 * i)) & 0xFF);
  }
  const char mask[4] = {0x12, 0x34, 0x56, 0x78};
  frame.append(mask, 4);
  for (std::size_t i = 0; i < n; ++i) frame += static_cast<char>(payload[i] ^ mask[i % 4]);
  return frame;
}

}  // namespace sarloc::dashboard::test
