// Fast DDS security fails open on a misspelled plugin: the start-up check must not.
#include "sarloc/dds/security_check.hpp"

#include <gtest/gtest.h>

#include <fstream>

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

void expect_refused(const DomainParticipantQos& qos, bool require, const std::string& expected) {
  try {
    check_security(qos, "test_profile", require);
    FAIL() << "expected ConfigError containing " << expected;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(SecurityCheck, CompleteSettingsPass) {
  EXPECT_TRUE(check_security(secure_qos(), "p", true));
  EXPECT_FALSE(check_security(DomainParticipantQos(), "p", false)) << "no security asked, none set";
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
  EXPECT_TRUE(check_security(qos, "p", true));
}

}  // namespace
}  // namespace sarloc::dds
