// Secrets are redacted from the mission text stored in recordings (issue 59), block and flow
// style alike, and the redacted text still loads as the same mission.
#include "sarloc/app/redact_secrets.hpp"

#include <gtest/gtest.h>

#include "sarloc/app/mission_config.hpp"

namespace sarloc::app {
namespace {

TEST(RedactSecrets, EveryTokenIsReplacedAndTheRestIsKept) {
  const std::string text =
      "# the command post\n"
      "mission: {name: secret mission, seed: 3}\n"
      "dashboard:\n"
      "  token: correct-horse-battery   # given to operators\n"
      "  operator_id: chief\n"
      "  view_token: look-but-do-not-touch\n"
      "other: {token: 'in-quotes-123', password: \"p w\", keep: token}\n"
      "list: [a, b]\n";
  const std::string redacted = redact_secrets(text);
  EXPECT_EQ(redacted.find("correct-horse-battery"), std::string::npos) << redacted;
  EXPECT_EQ(redacted.find("in-quotes-123"), std::string::npos) << redacted;
  EXPECT_EQ(redacted.find("look-but-do-not-touch"), std::string::npos) << redacted;
  EXPECT_EQ(redacted.find("p w"), std::string::npos) << redacted;
  EXPECT_NE(redacted.find("  token: \"(redacted)\"   # given to operators\n"), std::string::npos) << redacted;
  EXPECT_NE(redacted.find("name: secret mission"), std::string::npos) << "a word in a value is not a key";
  EXPECT_NE(redacted.find("keep: token}"), std::string::npos) << redacted;
  EXPECT_NE(redacted.find("operator_id: chief\n"), std::string::npos);
  EXPECT_NE(redacted.find("# the command post\n"), std::string::npos);
}

TEST(RedactSecrets, ARedactedMissionStillLoads) {
  const std::string text =
      "victims:\n  - {name: A, position: [0.0, 30.0, -1.0], moment: [0.01, 0.0, 0.005]}\n"
      "rescuers:\n  - {id: r1, team: t, start: [0.0, 0.0]}\n"
      "dashboard: {token: correct-horse-battery, port: 0}\n";
  const auto mission = load_mission_config_text(redact_secrets(text), "redacted.yaml", ".");
  EXPECT_EQ(mission.dashboard.token, "(redacted)");
  EXPECT_EQ(mission.dashboard.port, 0);
}

}  // namespace
}  // namespace sarloc::app
