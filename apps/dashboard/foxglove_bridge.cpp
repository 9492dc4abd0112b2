#include "foxglove_bridge.hpp"
#include "json_text.hpp"

#include <nlohmann/json.hpp>
#include <websocketpp/config/asio.hpp>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "sarloc/core/common/identifier.hpp"

namespace sarloc::dashboard {

namespace {

using Handle = websocketpp::connection_hdl;
constexpr const char* kSubprotocol = "foxglove.websocket.v1";

/// The `token` parameter of a request target "/?token=T&..." ("" when none).
std::string query_token(const std::string& resource) {
  const auto query = resource.find('?');
  if (query == std::string::npos) return "";
  for (std::size_t at = query + 1; at < resource.size();) {
    const std::size_t end = std::min(resource.find('&', at), resource.size());
    if (resource.compare(at, 6, "token=") == 0) return resource.substr(at + 6, end - at - 6);
    at = end + 1;
  }
  return "";
}

/// The feed's transport-independent face: FoxgloveBridge runs one Endpoint, over TCP or TLS.
class FeedEndpoint {
 public:
  virtual ~FeedEndpoint() = default;
  virtual int start() = 0;  ///< listens; returns the port
  virtual void stop() = 0;
  virtual std::size_t clients() const = 0;
  virtual std::size_t slow_dropped() const = 0;
  virtual void publish(std::uint32_t channel_id, std::shared_ptr<std::string> frame) = 0;
};

template <class Config>
struct Endpoint final : FeedEndpoint {
  using Server = websocketpp::server<Config>;
  FoxgloveBridgeConfig config;
  Server server;
  std::thread thread;
  std::vector<FoxgloveChannel> channels;
  mutable std::mutex mutex;
  // Per client: subscription id -> channel id.
  std::map<Handle, std::map<std::uint32_t, std::uint32_t>, std::owner_less<Handle>> subscribers;
  std::size_t slow_dropped_count = 0;
  bool running = false;

  void send_text(Handle handle, const nlohmann::json& message) {
    websocketpp::lib::error_code ignored;  // a client gone meanwhile: its close handler cleans up
    server.send(handle, json_text(message), websocketpp::frame::opcode::text, ignored);
  }

  bool admit(Handle handle) {
    auto connection = server.get_con_from_hdl(handle);
    const std::string origin = connection->get_request_header("Origin");
    const auto& allowed = config.allowed_origins;
    if (!origin.empty() && std::find(allowed.begin(), allowed.end(), origin) == allowed.end()) {
      spdlog::warn("Foxglove feed: a client from origin {} refused (dashboard.feed_origins)", printable_excerpt(origin));
      connection->set_status(websocketpp::http::status_code::forbidden);
      return false;
    }
    if (config.access && !config.access->may_view(query_token(connection->get_resource())) &&
        !config.access->has_session(connection->get_request_header("Cookie"))) {
      connection->set_status(websocketpp::http::status_code::unauthorized);
      return false;
    }
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (subscribers.size() >= config.max_clients) {
        connection->set_status(websocketpp::http::status_code::service_unavailable);
        return false;
      }
    }
    // Only clients that speak the Foxglove protocol, and we tell them so.
    for (const auto& protocol : connection->get_requested_subprotocols()) {
      if (protocol == kSubprotocol) {
        connection->select_subprotocol(kSubprotocol);
        return true;
      }
    }
    return false;
  }

  void on_open(Handle handle) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      subscribers[handle];
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
    subscribers.erase(handle);
  }

  void on_message(Handle handle, typename Server::message_ptr message) {
    // Whatever a client sends, the answer is at most a status: any JSON value, any bytes.
    try {
      const std::string problem = apply(handle, message->get_payload());
      if (!problem.empty()) send_status(handle, problem);
    } catch (const std::exception&) {
      send_status(handle, "a request that could not be read was ignored");
    }
  }

  /// Applies one client request; returns what was wrong with it ("" when nothing).
  std::string apply(Handle handle, const std::string& payload) {
    const nlohmann::json request = nlohmann::json::parse(payload, nullptr, false);
    if (request.is_discarded()) return "a message that is not JSON was ignored";
    if (!request.is_object() || !request.contains("op") || !request["op"].is_string()) return "a message without an \"op\" was ignored";
    const std::string op = request["op"].get<std::string>();
    std::lock_guard<std::mutex> lock(mutex);
    const auto client = subscribers.find(handle);
    if (client == subscribers.end()) return "";
    auto& subscriptions = client->second;
    const char* list_key = op == "subscribe" ? "subscriptions" : "subscriptionIds";
    if (op != "subscribe" && op != "unsubscribe") return "unknown op ignored";
    if (!request.contains(list_key) || !request[list_key].is_array()) return op + " without a list was ignored";
    std::size_t refused = 0;
    for (const auto& entry : request[list_key]) {
      if (op == "unsubscribe") {
        if (entry.is_number_unsigned()) subscriptions.erase(entry.get<std::uint32_t>());
        continue;
      }
      if (!entry.is_object() || !entry.contains("id") || !entry.contains("channelId") || !entry["id"].is_number_unsigned() ||
          !entry["channelId"].is_number_unsigned()) {
        ++refused;
        continue;
      }
      const auto id = entry["id"].get<std::uint64_t>();
      const auto channel = entry["channelId"].get<std::uint64_t>();
      if (id > 0xFFFFFFFFu || channel == 0 || channel > channels.size()) {
        ++refused;  // no such channel: nothing to send
        continue;
      }
      if (subscriptions.count(static_cast<std::uint32_t>(id)) == 0 && subscriptions.size() >= config.max_subscriptions_per_client) {
        ++refused;
        continue;
      }
      subscriptions[static_cast<std::uint32_t>(id)] = static_cast<std::uint32_t>(channel);
    }
    if (refused == 0) return "";
    return std::to_string(refused) + " subscription(s) refused: malformed, no such channel, or more than " +
           std::to_string(config.max_subscriptions_per_client) + " per client";
  }

  void send_status(Handle handle, const std::string& text) {
    send_text(handle, {{"op", "status"}, {"level", 1}, {"message", text}});
  }

  /// On the server's own thread (publish() posts it there): the queue a client has not read is
  /// measured where it grows, and a client behind by more than max_queued_bytes is dropped.
  void deliver(std::uint32_t channel_id, std::string& frame) {
    std::vector<std::pair<Handle, std::uint32_t>> targets;
    {
      std::lock_guard<std::mutex> lock(mutex);
      for (const auto& [handle, subscriptions] : subscribers) {
        for (const auto& [subscription, channel] : subscriptions) {
          if (channel == channel_id) targets.emplace_back(handle, subscription);
        }
      }
    }
    for (const auto& [handle, subscription] : targets) {
      websocketpp::lib::error_code ec;
      auto connection = server.get_con_from_hdl(handle, ec);
      if (ec) continue;
      if (connection->get_buffered_amount() + frame.size() > config.max_queued_bytes) {
        drop_slow(handle, connection);
        continue;
      }
      for (int i = 0; i < 4; ++i) frame[1 + i] = static_cast<char>((subscription >> (8 * i)) & 0xFF);
      connection->send(frame.data(), frame.size(), websocketpp::frame::opcode::binary);
    }
  }

  void drop_slow(Handle handle, const typename Server::connection_ptr& connection) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      const auto client = subscribers.find(handle);
      if (client == subscribers.end() || client->second.empty()) return;  // already being dropped
      client->second.clear();
      ++slow_dropped_count;
    }
    spdlog::warn("Foxglove feed: a client more than {} bytes behind was dropped", config.max_queued_bytes);
    websocketpp::lib::error_code ignored;
    connection->close(websocketpp::close::status::policy_violation, "too slow: more than the queue limit unread", ignored);
  }

  Endpoint(FoxgloveBridgeConfig bridge_config, std::vector<FoxgloveChannel> feed_channels)
      : config(std::move(bridge_config)), channels(std::move(feed_channels)) {
    auto& s = server;
    s.clear_access_channels(websocketpp::log::alevel::all);
    s.clear_error_channels(websocketpp::log::elevel::all);
    s.init_asio();
    s.set_reuse_addr(true);
    s.set_max_message_size(config.max_message_bytes);
    s.set_validate_handler([this](Handle handle) { return admit(handle); });
    s.set_open_handler([this](Handle h) { on_open(h); });
    s.set_close_handler([this](Handle h) { on_close(h); });
    s.set_fail_handler([this](Handle h) { on_close(h); });
    s.set_message_handler([this](Handle h, typename Server::message_ptr m) { on_message(h, m); });
    if constexpr (std::is_same_v<Config, websocketpp::config::asio_tls>) {
      // Read now: a certificate that cannot be read fails at start, not at the first client.
      auto context = make_tls_context(config.tls);
      s.set_tls_init_handler([context](Handle) { return context; });
    }
  }
  ~Endpoint() override { stop(); }

  int start() override {
    auto& s = server;
    websocketpp::lib::error_code ec;
    s.listen(config.bind_address, std::to_string(config.port), ec);
    if (ec) {
      throw std::runtime_error("Foxglove feed: cannot listen on " + config.bind_address + ":" + std::to_string(config.port) + ": " +
                               ec.message());
    }
    s.start_accept(ec);
    if (ec) throw std::runtime_error("Foxglove feed: " + ec.message());
    websocketpp::lib::asio::error_code endpoint_error;
    const int port = s.get_local_endpoint(endpoint_error).port();
    running = true;
    thread = std::thread([this] { server.run(); });
    return port;
  }

  void stop() override {
    if (!running) return;
    running = false;
    websocketpp::lib::error_code ignored;
    server.stop_listening(ignored);
    {
      std::lock_guard<std::mutex> lock(mutex);
      for (auto& [handle, subscriptions] : subscribers) server.close(handle, websocketpp::close::status::going_away, "", ignored);
    }
    server.stop();
    if (thread.joinable()) thread.join();
  }

  std::size_t clients() const override {
    std::lock_guard<std::mutex> lock(mutex);
    return subscribers.size();
  }

  std::size_t slow_dropped() const override {
    std::lock_guard<std::mutex> lock(mutex);
    return slow_dropped_count;
  }

  void publish(std::uint32_t channel_id, std::shared_ptr<std::string> frame) override {
    {
      std::lock_guard<std::mutex> lock(mutex);
      bool wanted = false;
      for (const auto& [handle, subscriptions] : subscribers) {
        for (const auto& [subscription, channel] : subscriptions) wanted = wanted || channel == channel_id;
      }
      if (!wanted || !running) return;
    }
    server.get_io_service().post([this, channel_id, frame] { deliver(channel_id, *frame); });
  }
};

}  // namespace


struct FoxgloveBridge::Impl {
  std::unique_ptr<FeedEndpoint> endpoint;
};

FoxgloveBridge::FoxgloveBridge(FoxgloveBridgeConfig config, std::vector<FoxgloveChannel> channels)
    : impl_(std::make_unique<Impl>()), port_(config.port) {
  if (config.tls.certificate.empty() != config.tls.private_key.empty()) {
    throw std::invalid_argument("Foxglove feed: a TLS certificate needs its private key, and the key its certificate");
  }
  if (config.tls.certificate.empty()) {
    impl_->endpoint = std::make_unique<Endpoint<websocketpp::config::asio>>(std::move(config), std::move(channels));
  } else {
    impl_->endpoint = std::make_unique<Endpoint<websocketpp::config::asio_tls>>(std::move(config), std::move(channels));
  }
}

FoxgloveBridge::~FoxgloveBridge() { stop(); }

void FoxgloveBridge::start() { port_ = impl_->endpoint->start(); }

void FoxgloveBridge::stop() { impl_->endpoint->stop(); }

std::size_t FoxgloveBridge::clients() const { return impl_->endpoint->clients(); }

std::size_t FoxgloveBridge::slow_clients_dropped() const { return impl_->endpoint->slow_dropped(); }

void FoxgloveBridge::publish(std::uint32_t channel_id, std::uint64_t timestamp_ns, const std::uint8_t* data, std::size_t size) {
  auto frame = std::make_shared<std::string>(1 + 4 + 8 + size, '\0');
  (*frame)[0] = 0x01;  // MessageData; the subscription id (bytes 1-4) is written per client
  for (int i = 0; i < 8; ++i) (*frame)[5 + i] = static_cast<char>((timestamp_ns >> (8 * i)) & 0xFF);
  std::copy(data, data + size, frame->begin() + 13);
  impl_->endpoint->publish(channel_id, std::move(frame));
}

}  // namespace sarloc::dashboard
