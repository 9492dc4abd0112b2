// config/dds/discovery-client.xml with a Fast DDS Discovery Server (fast-discovery-server, which
// `fastdds discovery` in deploy/systemd/sarloc-discovery-server.service runs): clients find each other through
// the server, and only through it.
#include <gtest/gtest.h>

#include "sarloc/app/child_process.hpp"
#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

using namespace std::chrono_literals;

std::shared_ptr<Participant> client(const std::string& name) {
  ParticipantConfig c;
  c.profiles_file = dds_config_dir() + "/discovery-client.xml";
  c.profile = "sarloc_discovery_client";
  c.allow_unauthenticated = true;  // a network profile; this test is about discovery, not security
  c.domain_id = test::kDomainDiscoveryServer;
  c.name = name;
  return std::make_shared<Participant>(c);
}

TEST(DiscoveryServer, ClientsMatchThroughTheServerOnly) {
  auto a = client("client-a");
  auto b = client("client-b");
  test::Inbox<::sarloc::IncidentSummary> inbox;
  Reader<::sarloc::IncidentSummary> reader(b, [&](const auto& s, const auto&) { inbox.push(s); });
  Writer<::sarloc::IncidentSummary> writer(a);
  EXPECT_FALSE(writer.wait_for_readers(1, 2s)) << "clients matched without a server: multicast is not off";

  // The server binary itself: `fastdds discovery` is a Python wrapper whose child outlives a
  // SIGTERM to the wrapper (systemd stops the unit's whole cgroup; a test stops one pid).
  app::ChildProcess server("discovery-server",
                           {"/usr/bin/fast-discovery-server", "-i", "0", "-l", "127.0.0.1", "-p", "11811"},
                           ::testing::TempDir() + "/discovery-server.log");
  ASSERT_TRUE(writer.wait_for_readers(1, 20s)) << "clients never matched through the discovery server";
  ::sarloc::IncidentSummary s;
  s.incident_id("through-the-server");
  ASSERT_TRUE(writer.write(s));
  const auto got = inbox.wait_for(1, 10s);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].incident_id().to_string(), "through-the-server");
  server.stop(std::chrono::seconds(5));
}

}  // namespace
}  // namespace sarloc::dds
