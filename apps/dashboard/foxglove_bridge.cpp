#include "foxglove_bridge.hpp"

#include <nlohmann/json.hpp>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include <stdexcept>

namespace sarloc::dashboard {

namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;
constexpr const char* kSubprotocol = "foxglove.websocket.v1";

}  // namespace

struct FoxgloveBridge::Impl {
  Server server;
  std::thread thread;
  std::vector<FoxgloveChannel> channels;
  mutable std::mutex mutex;
  // Per client: subscription id -> channel id.
  std::map<Handle, std::map<std::uint32_t, std::uint32_t>, std::owner_less<Handle>> clients;
  bool running = false;

  void send_text(Handle handle, const nlohmann::json& message) {
    websocketpp::lib::error_code ignored;  // a client gone meanwhile: its close handler cleans up
    server.send(handle, message.dump(), websocketpp::frame::opcode::text, ignored);
  }

  void on_open(Handle handle) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      clients[handle];
    }
    send_text(handle, {{"op", "serverInfo"},
                       {"name", "sarloc-dashboard"},
                       {"capabilities", nlohmann::json::array()},
                       {"supportedEncodings", nlohmann::json::array()},
                       {"metadata", nlohmann::json::object()}});
    nlohmann::json advertised = nlohmann::json::array();
    for (const auto& c : channels) {
      advertised.push_back({{"id", c.id},
                            {"topic", c.topic},
                            {"encoding", "cdr"},
                            {"schemaName", c.schema_name},
                            {"schema", c.schema},
                            {"schemaEncoding", "omgidl"}});
    }
    send_text(handle, {{"op", "advertise"}, {"channels", advertised}});
  }

  void on_close(Handle handle) {
    std::lock_guard<std::mutex> lock(mutex);
    clients.erase(handle);
  }

  void on_message(Handle handle, Server::message_ptr message) {
    nlohmann::json request;
    try {
      request = nlohmann::json::parse(message->get_payload());
    } catch (const std::exception&) {
      return send_status(handle, "a message that is not JSON was ignored");
    }
    const std::string op = request.value("op", "");
    std::lock_guard<std::mutex> lock(mutex);
    auto& subscriptions = clients[handle];
    try {
      if (op == "subscribe") {
        for (const auto& s : request.at("subscriptions")) {
          const auto channel = s.at("channelId").get<std::uint32_t>();
          if (channel == 0 || channel > channels.size()) continue;  // no such channel: nothing to send
          subscriptions[s.at("id").get<std::uint32_t>()] = channel;
        }
      } else if (op == "unsubscribe") {
        for (const auto& id : request.at("subscriptionIds")) subscriptions.erase(id.get<std::uint32_t>());
      }
    } catch (const std::exception&) {
      // A malformed request changes nothing and never stops the bridge.
    }
  }

  void send_status(Handle handle, const std::string& text) {
    send_text(handle, {{"op", "status"}, {"level", 1}, {"message", text}});
  }
};

FoxgloveBridge::FoxgloveBridge(std::string bind_address, int port, std::vector<FoxgloveChannel> channels)
    : impl_(std::make_unique<Impl>()), bind_address_(std::move(bind_address)), port_(port) {
  impl_->channels = std::move(channels);
  auto& s = impl_->server;
  s.clear_access_channels(websocketpp::log::alevel::all);
  s.clear_error_channels(websocketpp::log::elevel::all);
  s.init_asio();
  s.set_reuse_addr(true);
  s.set_validate_handler([this](Handle handle) {
    // Only clients that speak the Foxglove protocol, and we tell them so.
    auto connection = impl_->server.get_con_from_hdl(handle);
    for (const auto& protocol : connection->get_requested_subprotocols()) {
      if (protocol == kSubprotocol) {
        connection->select_subprotocol(kSubprotocol);
        return true;
      }
    }
    return false;
  });
  s.set_open_handler([this](Handle h) { impl_->on_open(h); });
  s.set_close_handler([this](Handle h) { impl_->on_close(h); });
  s.set_fail_handler([this](Handle h) { impl_->on_close(h); });
  s.set_message_handler([this](Handle h, Server::message_ptr m) { impl_->on_message(h, m); });
}

FoxgloveBridge::~FoxgloveBridge() { stop(); }

void FoxgloveBridge::start() {
  auto& s = impl_->server;
  websocketpp::lib::error_code ec;
  s.listen(bind_address_, std::to_string(port_), ec);
  if (ec) throw std::runtime_error("Foxglove feed: cannot listen on " + bind_address_ + ":" + std::to_string(port_) + ": " + ec.message());
  s.start_accept(ec);
  if (ec) throw std::runtime_error("Foxglove feed: " + ec.message());
  websocketpp::lib::asio::error_code endpoint_error;
  port_ = s.get_local_endpoint(endpoint_error).port();
  impl_->running = true;
  impl_->thread = std::thread([this] { impl_->server.run(); });
}

void FoxgloveBridge::stop() {
  if (!impl_->running) return;
  impl_->running = false;
  websocketpp::lib::error_code ignored;
  impl_->server.stop_listening(ignored);
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    for (auto& [handle, subscriptions] : impl_->clients) impl_->server.close(handle, websocketpp::close::status::going_away, "", ignored);
  }
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

std::size_t FoxgloveBridge::clients() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->clients.size();
}

void FoxgloveBridge::publish(std::uint32_t channel_id, std::uint64_t timestamp_ns, const std::uint8_t* data, std::size_t size) {
  std::vector<std::pair<Handle, std::uint32_t>> targets;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    for (const auto& [handle, subscriptions] : impl_->clients) {
      for (const auto& [subscription, channel] : subscriptions) {
        if (channel == channel_id) targets.emplace_back(handle, subscription);
      }
    }
  }
  if (targets.empty()) return;
  std::string frame(1 + 4 + 8 + size, '\0');
  frame[0] = 0x01;  // MessageData
  for (int i = 0; i < 8; ++i) frame[5 + i] = static_cast<char>((timestamp_ns >> (8 * i)) & 0xFF);
  std::copy(data, data + size, frame.begin() + 13);
  for (const auto& [handle, subscription] : targets) {
    for (int i = 0; i < 4; ++i) frame[1 + i] = static_cast<char>((subscription >> (8 * i)) & 0xFF);
    websocketpp::lib::error_code ignored;  // a slow or gone client must not stop the others
    impl_->server.send(handle, frame.data(), frame.size(), websocketpp::frame::opcode::binary, ignored);
  }
}

}  // namespace sarloc::dashboard
