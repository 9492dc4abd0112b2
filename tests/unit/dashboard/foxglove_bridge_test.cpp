// The Foxglove feed on its own (no DDS), as an attacker would try it (issue 59): any JSON value or
// bytes a client sends, a web page from another origin, thousands of subscriptions, a client
// that stops reading, and a seeded fuzz run. The bridge must stay up and keep serving a valid
// client; an exception escaping a handler would end this test process.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <boost/asio/ssl.hpp>

#include <filesystem>
#include <fstream>
#include <random>

#include "feed_client.hpp"
#include "foxglove_bridge.hpp"
#include "mutation.hpp"

namespace sarloc::dashboard {
namespace {

using test::client_frame;
using test::feed_handshake;
using test::FeedClient;
using test::RawSocket;
namespace fs = std::filesystem;

std::vector<FoxgloveChannel> two_channels() {
  return {{1, "sarloc/odometry", "sarloc::Odometry", "module sarloc { struct Odometry { long a; }; };"},
          {2, "sarloc/guidance", "sarloc::Guidance", "module sarloc { struct Guidance { long b; }; };"}};
}

class Feed : public ::testing::Test {
 protected:
  void SetUp() override { start(FoxgloveBridgeConfig{}); }
  void start(FoxgloveBridgeConfig config) {
    config.port = 0;
    bridge = std::make_unique<FoxgloveBridge>(config, two_channels());
    bridge->start();
  }
  void publish(std::uint32_t channel, const std::string& payload) {
    bridge->publish(channel, 42, reinterpret_cast<const std::uint8_t*>(payload.data()), payload.size());
  }
  /// A well-behaved client still subscribes and receives what is published.
  void expect_serving() {
    FeedClient valid(bridge->port());
    ASSERT_TRUE(valid.opened()) << "the feed no longer accepts a client";
    ASSERT_GE(valid.texts(2).size(), 2U) << "no serverInfo and advertise";
    ASSERT_TRUE(valid.send_text(R"({"op":"subscribe","subscriptions":[{"id":9,"channelId":2}]})"));
    // The subscription is applied on the server's thread: publish until it has arrived.
    for (int k = 0; k < 50 && valid.binaries(1, std::chrono::milliseconds(100)).empty(); ++k) publish(2, "payload");
    const auto frames = valid.binaries(1);
    ASSERT_FALSE(frames.empty()) << "a subscribed channel's payload never arrived";
    EXPECT_EQ(frames[0].substr(13), "payload");
  }
  std::unique_ptr<FoxgloveBridge> bridge;
};

std::size_t rss_kb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoul(line.substr(6));
  }
  return 0;
}

// Issue 59, finding 1: "[]" as a text frame ended the dashboard (exit 134): request.value("op")
// threw outside the try. Every JSON value, and every malformed request, now gets a status.
TEST_F(Feed, AnyJsonValueOrMalformedRequestGetsAStatusAndTheFeedStaysUp) {
  FeedClient client(bridge->port());
  ASSERT_TRUE(client.opened());
  const std::vector<std::string> hostile{
      "[]", "null", "42", "\"x\"", "{}", "true", R"({"op":5})", R"({"op":null})", R"({"op":"subscribe"})",
      R"({"op":"subscribe","subscriptions":5})", R"({"op":"subscribe","subscriptions":[1,"a",null,[]]})",
      R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1},{"id":1,"channelId":"a"},{"id":1e30,"channelId":1}]})",
      R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":1},{"id":1,"channelId":99}]})",
      R"({"op":"unsubscribe","subscriptionIds":[-5,"x",{}]})", R"({"op":"unsubscribe"})", R"({"op":"advertise","channels":[]})",
      "{", "not json"};
  for (const auto& message : hostile) ASSERT_TRUE(client.send_text(message)) << message;
  const auto texts = client.texts(2 + hostile.size() - 1);  // an unsubscribe of junk says nothing
  ASSERT_GE(texts.size(), 2 + hostile.size() - 1);
  for (std::size_t k = 2; k < texts.size(); ++k) EXPECT_EQ(nlohmann::json::parse(texts[k])["op"], "status") << texts[k];
  EXPECT_TRUE(client.open()) << "a malformed request does not even close its own connection";
  expect_serving();
}

// Issue 59, finding 1: the feed checked no Origin, so any page the commander opened (seen: a
// file:// page in Chromium) could read every topic. A browser's Origin must be on the list.
TEST_F(Feed, APageFromAnOriginNotAllowedIsRefused) {
  FoxgloveBridgeConfig config;
  config.allowed_origins = {"https://app.foxglove.dev"};
  start(config);
  for (const char* origin : {"null", "file://", "http://evil.example", "https://app.foxglove.dev.evil.example"}) {
    FeedClient page(bridge->port(), origin);
    EXPECT_FALSE(page.opened()) << origin;
  }
  FeedClient foxglove(bridge->port(), "https://app.foxglove.dev");
  EXPECT_TRUE(foxglove.opened());
  FeedClient desktop(bridge->port());
  EXPECT_TRUE(desktop.opened()) << "no Origin: not a web page";
}

// Issue 59, finding 6: the feed served every topic, raw field measurements included, to anyone.
// It takes the page's credentials: the view or operator token in the URL's query (Foxglove and
// Lichtblick keep it), or the page's session cookie.
TEST_F(Feed, AClientNeedsTheViewTokenOrThePagesSession) {
  auto sessions = std::make_shared<SessionStore>("look-but-do-not-touch", "correct-horse-battery");
  FoxgloveBridgeConfig config;
  config.access = sessions;
  start(config);
  EXPECT_FALSE(FeedClient(bridge->port()).opened()) << "no credential";
  EXPECT_FALSE(FeedClient(bridge->port(), "", "/?token=guessed-token").opened());
  EXPECT_FALSE(FeedClient(bridge->port(), "", "/", "sarloc_session=0123456789abcdef0123456789abcdef").opened());
  EXPECT_TRUE(FeedClient(bridge->port(), "", "/?token=look-but-do-not-touch").opened());
  EXPECT_TRUE(FeedClient(bridge->port(), "", "/?x=1&token=correct-horse-battery").opened());
  EXPECT_TRUE(FeedClient(bridge->port(), "", "/", "a=b; sarloc_session=" + sessions->open()).opened());
}

// Issue 59, deliverable 3: the feed over TLS with a certificate from make-dashboard-cert.sh. A
// client verifying against the incident CA completes the WebSocket handshake; a client speaking
// plain TCP to the same port gets no handshake.
TEST_F(Feed, OverTlsAClientVerifyingTheIncidentCaIsServedAndPlainTcpIsNot) {
  const fs::path dir = fs::temp_directory_path() / ("sarloc-feed-tls-" + std::to_string(getpid()));
  fs::remove_all(dir);
  ASSERT_EQ(std::system((std::string(SARLOC_SECURITY_DIR) + "/make-dashboard-cert.sh " + dir.string() + " 127.0.0.1 > /dev/null").c_str()), 0);
  FoxgloveBridgeConfig config;
  config.tls.certificate = (dir / "dashboard-tls" / "cert.pem").string();
  config.tls.private_key = (dir / "dashboard-tls" / "key.pem").string();
  start(config);

  namespace asio = boost::asio;
  asio::io_context io;
  asio::ssl::context context(asio::ssl::context::tls_client);
  context.load_verify_file((dir / "ca.pem").string());
  context.set_verify_mode(asio::ssl::verify_peer);
  asio::ssl::stream<asio::ip::tcp::socket> secure(io, context);
  secure.next_layer().connect({asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(bridge->port())});
  secure.handshake(asio::ssl::stream_base::client);  // throws when the certificate does not verify
  asio::write(secure, asio::buffer(feed_handshake()));
  asio::streambuf reply;
  asio::read_until(secure, reply, "\r\n\r\n");
  const std::string head(asio::buffers_begin(reply.data()), asio::buffers_end(reply.data()));
  EXPECT_EQ(head.rfind("HTTP/1.1 101", 0), 0U) << head;

  RawSocket plain(bridge->port());
  ASSERT_TRUE(plain.send(feed_handshake()));
  EXPECT_EQ(plain.receive_head().find("101"), std::string::npos) << "a WebSocket handshake in clear on the TLS port";
  fs::remove_all(dir);
}

// Issue 59: with dashboard.tls_client_ca the feed, like the page, serves only clients showing an
// operator's certificate (make-dashboard-client.sh): one gets the WebSocket handshake, a client
// without a certificate gets nothing.
TEST_F(Feed, WithAClientAuthorityOnlyAnOperatorsCertificateIsServed) {
  const fs::path dir = fs::temp_directory_path() / ("sarloc-feed-mtls-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const std::string security = std::string(SARLOC_SECURITY_DIR);
  ASSERT_EQ(std::system((security + "/make-dashboard-cert.sh " + dir.string() + " 127.0.0.1 > /dev/null && " +
                         security + "/make-dashboard-client.sh " + dir.string() + " commander > /dev/null")
                            .c_str()),
            0);
  FoxgloveBridgeConfig config;
  config.tls = {(dir / "dashboard-tls" / "cert.pem").string(), (dir / "dashboard-tls" / "key.pem").string(),
                (dir / "dashboard-clients" / "ca.pem").string()};
  start(config);

  namespace asio = boost::asio;
  // The reply's head to a WebSocket handshake over TLS, "" when the connection fails first.
  auto handshake_reply = [&](bool with_certificate) -> std::string {
    asio::io_context io;
    asio::ssl::context context(asio::ssl::context::tls_client);
    context.load_verify_file((dir / "ca.pem").string());
    context.set_verify_mode(asio::ssl::verify_peer);
    if (with_certificate) {
      context.use_certificate_file((dir / "dashboard-clients" / "commander" / "cert.pem").string(),
                                   asio::ssl::context::pem);
      context.use_private_key_file((dir / "dashboard-clients" / "commander" / "key.pem").string(),
                                   asio::ssl::context::pem);
    }
    asio::ssl::stream<asio::ip::tcp::socket> secure(io, context);
    try {
      secure.next_layer().connect({asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(bridge->port())});
      secure.handshake(asio::ssl::stream_base::client);
      asio::write(secure, asio::buffer(feed_handshake()));
      asio::streambuf reply;
      asio::read_until(secure, reply, "\r\n\r\n");
      return std::string(asio::buffers_begin(reply.data()), asio::buffers_end(reply.data()));
    } catch (const boost::system::system_error&) {
      return "";  // the server ended the handshake, or the connection after it (TLS 1.3)
    }
  };
  EXPECT_EQ(handshake_reply(true).rfind("HTTP/1.1 101", 0), 0U) << "the operator's certificate was refused";
  EXPECT_EQ(handshake_reply(false), "") << "a client without a certificate got an answer";
  fs::remove_all(dir);
}

// Issue 59, finding 4: one client subscribing 5000 ids to one topic, then not reading, took the
// dashboard from 52 to 431 MB in 6 s. A request is at most max_message_bytes (a larger one
// closes its connection), and subscriptions are capped per client.
TEST_F(Feed, SubscriptionsPerClientAreCapped) {
  auto subscribe = [](int count) {
    nlohmann::json request{{"op", "subscribe"}, {"subscriptions", nlohmann::json::array()}};
    for (int id = 0; id < count; ++id) request["subscriptions"].push_back({{"id", id}, {"channelId", 1}});
    return request.dump();
  };
  {
    FeedClient greedy(bridge->port());
    ASSERT_TRUE(greedy.opened());
    ASSERT_GT(subscribe(5000).size(), FoxgloveBridgeConfig{}.max_message_bytes);
    greedy.send_text(subscribe(5000));
    for (int k = 0; k < 50 && greedy.open(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_FALSE(greedy.open()) << "a 5000-subscription request is larger than a request may be";
  }
  FeedClient client(bridge->port());
  ASSERT_TRUE(client.opened());
  ASSERT_TRUE(client.send_text(subscribe(2000)));
  const auto texts = client.texts(3);
  ASSERT_GE(texts.size(), 3U);
  EXPECT_NE(texts[2].find("1936 subscription(s) refused"), std::string::npos) << texts[2];
  for (int k = 0; k < 50 && client.binaries(1, std::chrono::milliseconds(100)).empty(); ++k) publish(1, "x");
  const auto frames = client.binaries(1000, std::chrono::milliseconds(500));
  EXPECT_EQ(frames.size() % FoxgloveBridgeConfig{}.max_subscriptions_per_client, 0U) << "whole publishes of 64 copies";
  EXPECT_GE(frames.size(), FoxgloveBridgeConfig{}.max_subscriptions_per_client);
}

// A client that subscribes and stops reading is dropped once max_queued_bytes wait for it:
// the feed's memory stays bounded, and other clients are served.
TEST_F(Feed, AClientThatStopsReadingIsDroppedNotQueuedFor) {
  RawSocket stalled(bridge->port(), 4096);
  ASSERT_TRUE(stalled.connected());
  ASSERT_TRUE(stalled.send(feed_handshake()));
  ASSERT_NE(stalled.receive_head().find("101"), std::string::npos);
  ASSERT_TRUE(stalled.send(client_frame(0x1, R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1}]})")));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const std::size_t before = rss_kb();
  const std::string payload(64 * 1024, 'p');
  for (int k = 0; k < 1000 && bridge->slow_clients_dropped() == 0; ++k) {  // up to 64 MB
    publish(1, payload);
    if (k % 50 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(bridge->slow_clients_dropped(), 1U);
  const double grown_mb = (static_cast<double>(rss_kb()) - static_cast<double>(before)) / 1024.0;
  EXPECT_LT(grown_mb, 32.0) << "the queue limit is 4 MB";
  expect_serving();
}

// Seeded fuzz of the feed's inputs (issue 59, deliverable 1): 10 000 cases, mutated requests as
// text frames from a real client, and raw bytes after a real handshake (frames of any opcode,
// length and mask, truncated, or none at all). After them, a valid client is served.
TEST_F(Feed, TenThousandSeededHostileInputsLeaveItServing) {
  test::Mutator mutate(5901, "[{\"}]:,0-9e");
  auto& rng = mutate.rng();
  const std::vector<std::string> seeds{
      R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1}]})", R"({"op":"unsubscribe","subscriptionIds":[1]})",
      R"({"op":"subscribe","subscriptions":[{"id":2,"channelId":2},{"id":3,"channelId":1}]})", "[]", "{}"};
  const int total = test::fuzz_cases(), framed = total * 4 / 5;
  int cases = 0, closed = 0;
  // Text frames through a real client: four cases in five; websocketpp closes a connection on bytes
  // that are not UTF-8 (RFC 6455), and the client connects again.
  while (cases < framed) {
    FeedClient client(bridge->port());
    ASSERT_TRUE(client.opened()) << "case " << cases;
    while (cases < framed && client.open()) {
      ++cases;
      if (!client.send_text(mutate(seeds[rng() % seeds.size()]))) break;
    }
    ++closed;
  }
  // Raw bytes after the handshake: the fifth case, one connection each.
  for (int k = framed; k < total; ++k, ++cases) {
    RawSocket raw(bridge->port());
    ASSERT_TRUE(raw.connected()) << "case " << cases;
    std::string bytes = feed_handshake();
    const int how = static_cast<int>(rng() % 3);
    if (how == 0) {
      bytes += client_frame(static_cast<std::uint8_t>(rng() % 16), mutate(seeds[rng() % seeds.size()]), rng() % 4 != 0);
    } else if (how == 1) {
      std::string frame = client_frame(0x1, seeds[rng() % seeds.size()]);
      bytes += mutate(frame);
    } else {
      bytes += std::string(rng() % 64, static_cast<char>(rng() % 256));
    }
    raw.send(bytes);
    raw.finish_sending();
  }
  std::printf("%d hostile feed inputs, %d client connections closed by them or used up\n", cases, closed);
  expect_serving();
}

}  // namespace
}  // namespace sarloc::dashboard
