// Every app returns the documented exit codes for its command line (docs/operations.md): 0 for
// --help and --version, 2 for an unknown option, a bad value or a missing required option,
// never CLI11's own codes. No app gets as far as creating a DDS participant here.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace {

int exit_code_of(const std::string& command) {
  const int status = std::system((command + " >/dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

const std::vector<std::string> kApps = {"sarloc-core", "sarloc-rescuer",       "sarloc-command",   "sarloc-mission",
                                        "sarloc-eval", "sarloc-bench-latency", "sarloc-bench-echo", "sarloc-record",
                                        "sarloc-report", "sarloc-replay", "sarloc-dashboard", "sarloc-bench-recorder"};

std::string app(const std::string& name) { return std::string(SARLOC_BIN_DIR) + "/" + name; }

TEST(ExitCodes, HelpAndVersionExitZero) {
  for (const auto& a : kApps) {
    EXPECT_EQ(exit_code_of(app(a) + " --help"), 0) << a;
    EXPECT_EQ(exit_code_of(app(a) + " --version"), 0) << a;
  }
}

TEST(ExitCodes, UnknownOptionExitsTwo) {
  for (const auto& a : kApps) EXPECT_EQ(exit_code_of(app(a) + " --bogus"), 2) << a;
}

TEST(ExitCodes, BadLogLevelExitsTwo) {
  const std::string config = std::string(SARLOC_SOURCE_DIR) + "/config/missions/default.yaml";
  EXPECT_EQ(exit_code_of(app("sarloc-core") + " -c " + config + " --log-level loud"), 2);
  EXPECT_EQ(exit_code_of(app("sarloc-command") + " -c " + config + " --log-level loud"), 2);
  EXPECT_EQ(exit_code_of(app("sarloc-rescuer") + " -c " + config + " --id r1 --log-level loud"), 2);
  EXPECT_EQ(exit_code_of(app("sarloc-mission") + " --log-level loud"), 2);
  EXPECT_EQ(exit_code_of(app("sarloc-eval") + " --log-level loud avalanche"), 2);
  EXPECT_EQ(exit_code_of(app("sarloc-bench-latency") + " --log-level loud"), 2);
}

TEST(ExitCodes, BadValueOrMissingRequiredOptionExitsTwo) {
  EXPECT_EQ(exit_code_of(app("sarloc-core")), 2) << "-c is required";
  EXPECT_EQ(exit_code_of(app("sarloc-rescuer") + " -c x.yaml"), 2) << "--id is required";
  EXPECT_EQ(exit_code_of(app("sarloc-mission") + " --domain notanumber"), 2);
  EXPECT_EQ(exit_code_of(app("sarloc-eval")), 2) << "a subcommand is required";
  EXPECT_EQ(exit_code_of(app("sarloc-eval") + " avalanche --trials many"), 2);
}

TEST(ExitCodes, RecordingToolsRefuseWhatIsNotARecording) {
  EXPECT_EQ(exit_code_of(app("sarloc-report")), 2) << "the recording is required";
  const std::string text = std::string(SARLOC_SOURCE_DIR) + "/README.md";
  EXPECT_EQ(exit_code_of(app("sarloc-report") + " " + text + " -o /dev/null"), 4) << "not MCAP";
  EXPECT_EQ(exit_code_of(app("sarloc-report") + " " + text + " -o /dev/null --basemap " + text), 3)
      << "a --basemap that is not MBTiles: refused before the recording is read";
  EXPECT_EQ(exit_code_of(app("sarloc-record") + " --recover /nonexistent.mcap"), 4);
  EXPECT_EQ(exit_code_of(app("sarloc-record")), 3) << "-c is required unless --recover";
}

TEST(ExitCodes, MissingConfigFileIsAConfigurationErrorNotUsage) {
  EXPECT_EQ(exit_code_of(app("sarloc-core") + " -c /nonexistent/mission.yaml"), 3);
}

TEST(ExitCodes, AnUnknownEvaluationRowIsAConfigurationError) {
  const std::string house = std::string(SARLOC_SOURCE_DIR) + "/config/buildings/house-125.yaml";
  EXPECT_EQ(exit_code_of(app("sarloc-eval") + " firefighter --building " + house + " --rows known/weights,nosuch"), 3);
}

TEST(ExitCodes, AMisplacedProcessIsAConfigurationError) {
  const std::string mission = app("sarloc-mission") + " " + SARLOC_SOURCE_DIR + "/config/missions/default.yaml";
  EXPECT_EQ(exit_code_of(mission + " --launcher /bin/true --host core"), 3) << "no =HOST";
  EXPECT_EQ(exit_code_of(mission + " --launcher /bin/true --host core=h2 --host nosuch=h9"), 3) << "no such process";
  EXPECT_EQ(exit_code_of(mission + " --host core=h2"), 3) << "no launcher";
}

}  // namespace
