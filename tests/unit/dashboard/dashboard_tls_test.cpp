// The page over TLS (issue 59, deliverable 3): a certificate from
// deploy/security/make-dashboard-cert.sh serves HTTPS that a client verifying against the
// incident CA accepts, the session cookie is Secure, plain HTTP gets nothing; and any address but
// loopback without TLS is refused with a message that says what to do.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

// Eigen before httplib.h: the resolver header httplib pulls in defines `_res`, a name Eigen uses.
#include "dashboard_server.hpp"
#include "sarloc/core/common/errors.hpp"

#include <httplib.h>

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

TEST(DashboardTls, ThePageOverTlsVerifiesAgainstTheIncidentCaAndItsCookieIsSecure) {
  const fs::path dir = fs::temp_directory_path() / ("sarloc-dashboard-tls-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const std::string make = std::string(SARLOC_SECURITY_DIR) + "/make-dashboard-cert.sh " + dir.string() + " 127.0.0.1 > /dev/null";
  ASSERT_EQ(std::system(make.c_str()), 0) << make;
  auto config = config_on("127.0.0.1");
  config.tls_certificate = (dir / "dashboard-tls" / "cert.pem").string();
  config.tls_private_key = (dir / "dashboard-tls" / "key.pem").string();
  PictureState state{PictureStateConfig{}, [] { return TimestampNs{0}; }, 0};
  DashboardServer server(config, state, [](std::uint32_t, const std::string&) { return false; });
  server.start();
  ASSERT_TRUE(server.tls());

  httplib::SSLClient secure("127.0.0.1", server.port());
  secure.set_ca_cert_path((dir / "ca.pem").string().c_str());
  secure.enable_server_certificate_verification(true);
  const auto page = secure.Get("/");
  ASSERT_TRUE(page) << "HTTPS verified against the incident CA failed: " << httplib::to_string(page.error());
  EXPECT_EQ(page->status, 200);
  const auto opened = secure.Post("/api/session", R"({"token":"look-but-do-not-touch"})", "application/json");
  ASSERT_TRUE(opened);
  EXPECT_NE(opened->get_header_value("Set-Cookie").find("; Secure"), std::string::npos) << opened->get_header_value("Set-Cookie");

  httplib::SSLClient stranger("127.0.0.1", server.port());
  stranger.enable_server_certificate_verification(true);  // the system's authorities only
  EXPECT_FALSE(stranger.Get("/")) << "a certificate of the incident CA verified without it";
  httplib::Client plain("127.0.0.1", server.port());
  plain.set_read_timeout(2, 0);
  const auto clear = plain.Get("/");
  EXPECT_TRUE(!clear || clear->status != 200) << "the page was served in clear on the TLS port";
  server.stop();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sarloc::dashboard
