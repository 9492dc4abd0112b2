// The options every node takes (--domain, --epoch-ns, --epoch-wall-ns, --speedup): a bad one is
// refused naming the option and the value before any participant or clock is made.
#include "sarloc/app/node_options.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "support/config_messages.hpp"

namespace sarloc::app {
namespace {

TEST(NodeOptions, EachOptionIsCheckedNamingItsValue) {
  EXPECT_EQ(sarloc::test::validation_error(NodeOptions{}), "");
  const std::vector<std::pair<void (*)(NodeOptions&), std::string>> cases = {
      {[](NodeOptions& o) { o.domain = 300; }, "--domain = 300: must be in [0, 232] (absent: dds.domain_id)"},
      {[](NodeOptions& o) { o.epoch_ns = -5; }, "--epoch-ns = -5: must be >= 0 (absent: now)"},
      {[](NodeOptions& o) { o.speedup = 250.0; }, "--speedup = 250: must be in [0.1, 100] (as mission.speedup)"},
      {[](NodeOptions& o) { o.speedup = 2.5; }, ""},
  };
  for (const auto& [change, message] : cases) {
    NodeOptions options;
    change(options);
    EXPECT_EQ(sarloc::test::validation_error(options), message);
  }
}

namespace fs = std::filesystem;

const std::string kTwoRescuersInTwoSectors = R"(
victims:
  - {name: A, position: [0.0, 30.0, -1.0], moment: [0.01, 0.0, 0.005]}
rescuers:
  - {id: r1, team: t, start: [0.0, 0.0], sector: west}
  - {id: r2, team: t, start: [5.0, 0.0], sector: east}
sectors: [{name: west}, {name: east}]
)";

// dds.security_dir: each node loads its own identity's secure.xml (make-certs.sh's layout) and
// requires DDS Security; a node whose identity was not issued is refused by name, before any
// participant exists, with the command that issues the mission's identities.
TEST(NodeOptions, WithASecurityDirEachNodeLoadsItsOwnIdentityAndOneNotIssuedIsRefusedByName) {
  const fs::path dir = fs::temp_directory_path() / ("sarloc-node-identity-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "sec" / "r1");
  std::ofstream(dir / "sec" / "r1" / "secure.xml") << "<dds/>";
  const auto mission = load_mission_config_text(kTwoRescuersInTwoSectors + "dds: {security_dir: sec, domain_id: 7}\n",
                                                "m.yaml", dir.string());
  EXPECT_EQ(mission.security_dir, (dir / "sec").string()) << "resolved against the mission file's folder";

  const auto r1 = participant_config(mission, -1, "rescuer-r1", "r1");
  EXPECT_EQ(r1.profiles_file, (dir / "sec" / "r1" / "secure.xml").string());
  EXPECT_EQ(r1.profile, "sarloc_secure");
  EXPECT_TRUE(r1.require_security);
  EXPECT_EQ(r1.name, "rescuer-r1");
  EXPECT_EQ(r1.domain_id, 7U);

  const auto refusal =
      sarloc::test::config_error_of([&] { (void)participant_config(mission, -1, "rescuer-r2", "r2"); });
  EXPECT_NE(refusal.find("no identity 'r2'"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("make-certs.sh"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("--identities"), std::string::npos) << refusal;

  const auto plain = load_mission_config_text(kTwoRescuersInTwoSectors, "m.yaml", dir.string());
  const auto unsecured = participant_config(plain, -1, "rescuer-r2", "r2");
  EXPECT_EQ(unsecured.profile, "sarloc_localhost") << "without the key, the mission's profile as before";
  EXPECT_FALSE(unsecured.require_security);
  fs::remove_all(dir);
}

TEST(NodeOptions, ASecurityDirWithAProfileOfItsOwnIsRefused) {
  for (const std::string dds :
       {"dds: {security_dir: sec, profile: sarloc_lan}\n", "dds: {security_dir: sec, profiles_file: lan.xml}\n"}) {
    const auto message = sarloc::test::config_error_of(
        [&] { (void)load_mission_config_text(kTwoRescuersInTwoSectors + dds, "m.yaml"); });
    EXPECT_NE(message.find("m.yaml: dds.security_dir = 'sec'"), std::string::npos) << message;
    EXPECT_NE(message.find("must not be set with it"), std::string::npos) << message;
  }
}

// The identities sarloc-mission --identities prints, as make-certs.sh takes them: the node ids
// the nodes really use (a core daemon per sector, every incident command instance).
TEST(NodeOptions, AMissionNamesEveryIdentityItsNodesLoad) {
  const auto mission = load_mission_config_text(kTwoRescuersInTwoSectors, "m.yaml");
  const std::vector<std::string> expected = {"core:" + mission.core_config("west").node_id,
                                             "core:" + mission.core_config("east").node_id,
                                             "command:" + mission.command_config(1).node_id,
                                             "command:" + mission.command_config(2).node_id,
                                             "device:r1",
                                             "device:r2",
                                             "dashboard:dashboard",
                                             "recorder:recorder",
                                             "recorder:mission"};
  EXPECT_EQ(mission.security_identities(), expected);
  EXPECT_EQ(expected[0], "core:sarloc-core-west");
  EXPECT_EQ(expected[2], "command:sarloc-command-1");
}

}  // namespace
}  // namespace sarloc::app
