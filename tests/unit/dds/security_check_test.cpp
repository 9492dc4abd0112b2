// Fast DDS security fails open on a misspelled plugin: the start-up check must not. And a
// profile that reaches beyond this machine runs unsecured only when the mission says so.
#include "sarloc/dds/security_check.hpp"

#include <gtest/gtest.h>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>

#include <fstream>
#include <memory>

#include "sarloc/core/common/errors.hpp"

namespace sarloc::dds {
namespace {

using eprosima::fastdds::dds::DomainParticipantQos;

DomainParticipantQos secure_qos() {
  DomainParticipantQos qos;
  auto& p = qos.properties().properties();
  p.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  p.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  p.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
  return qos;
}

/// sarloc_localhost's transports: shared memory and UDP on 127.0.0.1 only.
DomainParticipantQos loopback_qos(const std::string& udp_interface = "127.0.0.1") {
  DomainParticipantQos qos;
  qos.transport().use_builtin_transports = false;
  qos.transport().user_transports.push_back(std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>());
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  if (!udp_interface.empty()) udp->interfaceWhiteList.push_back(udp_interface);
  qos.transport().user_transports.push_back(udp);
  return qos;
}

void expect_refused(const DomainParticipantQos& qos, bool require, const std::string& expected,
                    bool allow_unauthenticated = false) {
  try {
    check_security(qos, "test_profile", require, allow_unauthenticated);
    FAIL() << "expected ConfigError containing " << expected;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(SecurityCheck, CompleteSettingsPass) {
  EXPECT_TRUE(check_security(secure_qos(), "p", true, false));
  EXPECT_FALSE(check_security(loopback_qos(), "p", false, false)) << "on loopback: no security asked, none set";
}

// Issue 59: the shipped deployment runs DDS Security by default. A profile whose packets can
// leave this machine is refused unsecured unless dds.allow_unauthenticated says so.
TEST(SecurityCheck, UnsecuredBeyondLoopbackIsRefusedUnlessAllowed) {
  EXPECT_FALSE(network_reach(loopback_qos()));
  expect_refused(DomainParticipantQos(), false, "builtin transports use every interface");
  expect_refused(loopback_qos(""), false, "no interface whitelist");
  expect_refused(loopback_qos("192.168.1.5"), false, "allows interface 192.168.1.5");
  expect_refused(loopback_qos("eth0"), false, "dds.allow_unauthenticated: true");
  EXPECT_FALSE(check_security(loopback_qos("eth0"), "p", false, true)) << "a drill on a closed network, as stated";
  EXPECT_FALSE(check_security(DomainParticipantQos(), "p", false, true));
  EXPECT_TRUE(check_security(secure_qos(), "p", false, false)) << "secured: any transport";
}

TEST(SecurityCheck, MisspelledPluginIsRefusedNotRunUnsecured) {
  auto qos = secure_qos();
  for (auto& p : qos.properties().properties()) {
    if (p.name() == "dds.sec.auth.plugin") p.value("builtin.PKI-DH2");
  }
  expect_refused(qos, false, "dds.sec.auth.plugin = 'builtin.PKI-DH2'");
}

TEST(SecurityCheck, PartialSettingsAreRefused) {
  DomainParticipantQos qos;
  qos.properties().properties().emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  expect_refused(qos, false, "dds.sec.access.plugin = '(not set)'");
}

TEST(SecurityCheck, RequiredButAbsentIsRefused) {
  expect_refused(DomainParticipantQos(), true, "sets no dds.sec.* property");
}

TEST(SecurityCheck, MissingCertificateFileIsNamed) {
  auto qos = secure_qos();
  qos.properties().properties().emplace_back("dds.sec.auth.builtin.PKI-DH.identity_ca", "file:///nonexistent/ca.pem");
  expect_refused(qos, false, "identity_ca = 'file:///nonexistent/ca.pem': no such file");
  const std::string present = ::testing::TempDir() + "/ca.pem";
  std::ofstream(present) << "x";
  qos.properties().properties().back().value("file:" + present);
  expect_refused(qos, false, "must be given as file://<path>");
  qos.properties().properties().back().value("file://" + present);
  EXPECT_TRUE(check_security(qos, "p", true, false));
}

}  // namespace
}  // namespace sarloc::dds
