// The page over TLS (issue 59, deliverable 3): a certificate from
// deploy/security/make-dashboard-cert.sh serves HTTPS that a client verifying against the
// incident CA accepts, the session cookie is Secure, plain HTTP gets nothing; and any address but
// loopback without TLS is refused with a message that says what to do. TLS ends in the
// connection gate, so a client that dribbles its request inside TLS holds no server thread.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

// Eigen before httplib.h: the resolver header httplib pulls in defines `_res`, a name Eigen uses
// (an order clang-format's include regrouping would undo).
// clang-format off
#include "dashboard_server.hpp"
#include "raw_socket.hpp"
#include "sarloc/core/common/errors.hpp"

#include <httplib.h>
#include <openssl/ssl.h>
// clang-format on

namespace sarloc::dashboard {
namespace {

namespace fs = std::filesystem;

DashboardServerConfig config_on(const std::string& address) {
  DashboardServerConfig config;
  config.bind_address = address;
  config.port = 0;
  config.token = "correct-horse-battery";
  config.view_token = "look-but-do-not-touch";
  return config;
}

TEST(DashboardTls, BeyondLoopbackWithoutTlsIsRefusedSayingWhatToDo) {
  PictureState state{PictureStateConfig{}, [] { return TimestampNs{0}; }, 0};
  try {
    DashboardServer server(config_on("0.0.0.0"), state, [](std::uint32_t, const std::string&) { return false; });
    FAIL() << "plain HTTP beyond loopback was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("needs TLS"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("make-dashboard-cert.sh"), std::string::npos) << e.what();
  }
  auto listed = config_on("0.0.0.0");
  listed.tls_certificate = "/nonexistent/cert.pem";
  listed.tls_private_key = "/nonexistent/key.pem";
  try {
    DashboardServer server(listed, state, [](std::uint32_t, const std::string&) { return false; });
    FAIL() << "0.0.0.0 without dashboard.hosts was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("dashboard.hosts"), std::string::npos) << e.what();
  }
  for (const char* loopback : {"127.0.0.1", "localhost", "::1"}) EXPECT_TRUE(is_loopback_address(loopback)) << loopback;
  EXPECT_FALSE(is_loopback_address("10.0.0.5"));
  auto half = config_on("127.0.0.1");
  half.tls_certificate = "/nonexistent/cert.pem";
  EXPECT_THROW(DashboardServer(half, state, [](std::uint32_t, const std::string&) { return false; }), ConfigError)
      << "a certificate without its key";
  half.tls_private_key = "/nonexistent/key.pem";
  EXPECT_THROW(DashboardServer(half, state, [](std::uint32_t, const std::string&) { return false; }), ConfigError)
      << "files that are not there";
}

/// A dashboard over TLS on loopback, with a certificate of the incident CA from
/// make-dashboard-cert.sh (in a directory of its own, removed after).
class PageOverTls : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::remove_all(dir);
    const std::string make =
        std::string(SARLOC_SECURITY_DIR) + "/make-dashboard-cert.sh " + dir.string() + " 127.0.0.1 > /dev/null";
    ASSERT_EQ(std::system(make.c_str()), 0) << make;
    auto config = config_on("127.0.0.1");
    config.tls_certificate = (dir / "dashboard-tls" / "cert.pem").string();
    config.tls_private_key = (dir / "dashboard-tls" / "key.pem").string();
    server = std::make_unique<DashboardServer>(config, state, [](std::uint32_t, const std::string&) { return false; });
    server->start();
  }
  void TearDown() override {
    if (server) server->stop();
    fs::remove_all(dir);
  }
  /// A client that verifies the page's certificate against the incident CA.
  std::unique_ptr<httplib::SSLClient> verifying_client() {
    auto client = std::make_unique<httplib::SSLClient>("127.0.0.1", server->port());
    client->set_ca_cert_path((dir / "ca.pem").string().c_str());
    client->enable_server_certificate_verification(true);
    return client;
  }

  const fs::path dir = fs::temp_directory_path() / ("sarloc-dashboard-tls-" + std::to_string(getpid()));
  PictureState state{PictureStateConfig{}, [] { return TimestampNs{0}; }, 0};
  std::unique_ptr<DashboardServer> server;
};

TEST_F(PageOverTls, ThePageOverTlsVerifiesAgainstTheIncidentCaAndItsCookieIsSecure) {
  ASSERT_TRUE(server->tls());

  auto secure = verifying_client();
  const auto page = secure->Get("/");
  ASSERT_TRUE(page) << "HTTPS verified against the incident CA failed: " << httplib::to_string(page.error());
  EXPECT_EQ(page->status, 200);
  const auto opened = secure->Post("/api/session", R"({"token":"look-but-do-not-touch"})", "application/json");
  ASSERT_TRUE(opened);
  EXPECT_NE(opened->get_header_value("Set-Cookie").find("; Secure"), std::string::npos) << opened->get_header_value("Set-Cookie");

  httplib::SSLClient stranger("127.0.0.1", server->port());
  stranger.enable_server_certificate_verification(true);  // the system's authorities only
  EXPECT_FALSE(stranger.Get("/")) << "a certificate of the incident CA verified without it";
  httplib::Client plain("127.0.0.1", server->port());
  plain.set_read_timeout(2, 0);
  const auto clear = plain.Get("/");
  EXPECT_TRUE(!clear || clear->status != 200) << "the page was served in clear on the TLS port";
}

// A client that completes its TLS handshake and then dribbles its request (issue 59, "many
// addresses, what is left"). While TLS passed through the gate to cpp-httplib's SSLServer, each
// such client held a server thread until the deadline, and 96 of three addresses held all 72 of
// them (max_streams 64 + 8): the commander's page timed out. The gate now ends TLS and holds the
// decrypted request until it is whole, as it holds a plain one.
TEST_F(PageOverTls, SlowTlsClientsOfManyAddressesHoldNoServerThread) {
  // The attackers do not verify the certificate: they only want the threads.
  std::unique_ptr<SSL_CTX, decltype(&SSL_CTX_free)> attacker_tls(SSL_CTX_new(TLS_client_method()), SSL_CTX_free);
  struct SlowClient {
    std::unique_ptr<test::RawSocket> socket;
    std::unique_ptr<SSL, decltype(&SSL_free)> tls{nullptr, SSL_free};
  };
  std::vector<SlowClient> slow;
  const std::string head = "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n";
  for (const char* from : {"127.0.0.2", "127.0.0.3", "127.0.0.4"}) {
    for (int i = 0; i < 32; ++i) {
      SlowClient c;
      c.socket = std::make_unique<test::RawSocket>(server->port(), 0, from);
      ASSERT_TRUE(c.socket->connected());
      c.tls.reset(SSL_new(attacker_tls.get()));
      SSL_set_fd(c.tls.get(), c.socket->fd());
      ASSERT_EQ(SSL_connect(c.tls.get()), 1) << "TLS handshake " << slow.size();
      ASSERT_EQ(SSL_write(c.tls.get(), head.data(), static_cast<int>(head.size())), static_cast<int>(head.size()));
      slow.push_back(std::move(c));
    }
  }
  for (auto& c : slow) ASSERT_EQ(SSL_write(c.tls.get(), "X", 1), 1);  // a byte, and the request still not whole

  auto commander = verifying_client();
  commander->set_connection_timeout(std::chrono::seconds(1));
  commander->set_read_timeout(std::chrono::seconds(1));
  const auto page = commander->Get("/");
  ASSERT_TRUE(page) << "the commander's page over TLS failed behind 96 slow TLS clients: "
                    << httplib::to_string(page.error());
  EXPECT_EQ(page->status, 200);
  EXPECT_EQ(server->connection_counters().refused_address, 0U);
}

}  // namespace
}  // namespace sarloc::dashboard
