// deploy/security/make-certs.sh produces material Fast DDS accepts: two secured nodes talk,
// an unauthenticated participant on the same domain hears nothing.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "sarloc/dds/reader.hpp"
#include "sarloc/dds/writer.hpp"
#include "support/dds_test_domains.hpp"
#include "support/dds_test_helpers.hpp"

namespace sarloc::dds {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

ParticipantConfig secure_config(const fs::path& dir, const std::string& node) {
  ParticipantConfig c;
  c.profiles_file = (dir / node / "secure.xml").string();
  c.profile = "sarloc_secure";
  c.domain_id = test::kDomainSecurity;
  c.name = node;
  c.require_security = true;
  return c;
}

::sarloc::IncidentSummary summary(std::uint32_t n) {
  ::sarloc::IncidentSummary s;
  s.incident_id("secured");
  s.victims_total(n);
  return s;
}

TEST(Security, SecuredNodesTalkAndAnUnauthenticatedOneHearsNothing) {
  const fs::path dir = fs::temp_directory_path() / ("sarloc-security-test-" + std::to_string(getpid()));
  fs::remove_all(dir);
  const std::string make = std::string(SARLOC_SECURITY_DIR) + "/make-certs.sh " + dir.string() + " alpha bravo > /dev/null";
  ASSERT_EQ(std::system(make.c_str()), 0) << make;

  // bravo publishes from another process: each process loads one node's secure.xml.
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    int code = 1;
    try {
      auto bravo = std::make_shared<Participant>(secure_config(dir, "bravo"));
      Writer<::sarloc::IncidentSummary> writer(bravo);
      if (bravo->secured() && writer.wait_for_readers(1, 20s)) {
        for (std::uint32_t i = 1; i <= 20; ++i) {
          writer.write(summary(i));
          std::this_thread::sleep_for(100ms);
        }
        code = 0;
      }
    } catch (...) {
    }
    _exit(code);
  }

  auto alpha = std::make_shared<Participant>(secure_config(dir, "alpha"));
  EXPECT_TRUE(alpha->secured());
  test::Inbox<::sarloc::IncidentSummary> secured_inbox;
  Reader<::sarloc::IncidentSummary> secured_reader(alpha, [&](const auto& s, const auto&) { secured_inbox.push(s); });
  auto outsider = test::make_participant(test::kDomainSecurity, "outsider");
  EXPECT_FALSE(outsider->secured());
  test::Inbox<::sarloc::IncidentSummary> outsider_inbox;
  Reader<::sarloc::IncidentSummary> outsider_reader(outsider, [&](const auto& s, const auto&) { outsider_inbox.push(s); });

  const auto got = secured_inbox.wait_for(3, 30s);
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the secured writer never matched";
  EXPECT_GE(got.size(), 3U) << "secured nodes did not exchange data";
  EXPECT_TRUE(outsider_inbox.wait_for(1, 0ms).empty()) << "an unauthenticated participant received secured data";
  EXPECT_EQ(outsider_reader.matched_writers(), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sarloc::dds
