// The configuration keys the docs document are exactly those the loaders accept: every key of
// docs/configuration.md (mission file) and of the parameter table of
// docs/estimation/avalanche.md (sog, search, simulation, evaluation) is read by a loader, and
// every key a loader reads is documented. A key added to one side only fails here.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "eval_config.hpp"
#include "sarloc/app/floor_plan_yaml.hpp"
#include "sarloc/app/mission_config.hpp"
#include "sarloc/app/yaml_reader.hpp"

namespace sarloc::app {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = SARLOC_SOURCE_DIR;

std::vector<std::string> lines_of(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, const std::string& sep) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (std::size_t at; (at = s.find(sep, from)) != std::string::npos; from = at + sep.size()) {
    out.push_back(trim(s.substr(from, at - from)));
  }
  out.push_back(trim(s.substr(from)));
  return out;
}

// First cell of line i if it is a table body row, else "" (header, separator, prose).
std::string key_cell(const std::vector<std::string>& lines, std::size_t i) {
  const std::string& line = lines[i];
  if (line.rfind("| ", 0) != 0 || line.rfind("|---", 0) == 0) return "";
  if (i + 1 < lines.size() && lines[i + 1].rfind("|---", 0) == 0) return "";  // a header row
  std::string cell = trim(line.substr(1, line.find('|', 1) - 1));
  for (const std::string tag : {" (required)", "`"}) {
    for (auto at = cell.find(tag); at != std::string::npos; at = cell.find(tag)) cell.erase(at, tag.size());
  }
  return cell;
}

// docs/configuration.md, "## Mission file": one "### `section`" per section, a table of keys.
std::set<std::string> documented_mission_keys() {
  std::set<std::string> keys;
  bool in_mission = false;
  std::string prefix;
  const auto lines = lines_of(kSource / "docs/configuration.md");
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    if (line.rfind("## ", 0) == 0) in_mission = line == "## Mission file";
    if (!in_mission) continue;
    if (line.rfind("### `", 0) == 0) {
      const auto end = line.find('`', 5);
      prefix = line.substr(5, end - 5) + (line.find("list") != std::string::npos ? "[]" : "");
      continue;
    }
    const std::string cell = key_cell(lines, i);
    if (cell.empty() || prefix.empty() || cell.rfind("every key of", 0) == 0) continue;
    for (const auto& key : split(cell, ", ")) keys.insert(prefix + "." + key);
  }
  return keys;
}

// The table(s) of section `heading` of `doc`: full key paths; "a.b, c" means a.b and a.c.
std::set<std::string> documented_table_keys(const fs::path& doc, const std::string& heading) {
  std::set<std::string> keys;
  bool in_parameters = false;
  const auto lines = lines_of(doc);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].rfind("## ", 0) == 0) in_parameters = lines[i].rfind(heading, 0) == 0;
    if (!in_parameters) continue;
    const std::string cell = key_cell(lines, i);
    if (cell.empty()) continue;
    const auto parts = split(cell, ", ");
    const std::string section = parts[0].substr(0, parts[0].rfind('.') + 1);
    for (const auto& key : parts) keys.insert(key.find('.') == std::string::npos ? section + key : key);
  }
  return keys;
}

// docs/estimation/avalanche.md, "## Parameters".
std::set<std::string> documented_model_keys() {
  return documented_table_keys(kSource / "docs/estimation/avalanche.md", "## Parameters");
}

// What a loader asked for, without the maps and lists that only hold other keys.
std::set<std::string> leaves(const std::set<std::string>& asked) {
  std::set<std::string> out;
  for (const auto& key : asked) {
    const bool parent = std::any_of(asked.begin(), asked.end(), [&](const std::string& other) {
      return other.size() > key.size() && other.rfind(key, 0) == 0 && (other[key.size()] == '.' || other[key.size()] == '[');
    });
    if (!parent) out.insert(key);
  }
  return out;
}

std::string difference(const std::set<std::string>& a, const std::set<std::string>& b) {
  std::string out;
  for (const auto& k : a) {
    if (b.count(k) == 0) out += " " + k;
  }
  return out;
}

std::vector<fs::path> yaml_files(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".yaml") out.push_back(entry.path());
  }
  return out;
}

TEST(ConfigDocs, MissionKeysDocumentedAreExactlyThoseTheLoaderReads) {
  std::set<std::string> documented = documented_mission_keys();
  ASSERT_GT(documented.size(), 30U) << "docs/configuration.md: mission tables not found";
  for (const auto& key : documented_model_keys()) {
    if (key.rfind("evaluation.", 0) != 0) documented.insert(key);  // sog, search, simulation
  }
  // firefighter.filter: every key of the firefighter evaluation's filter: section.
  for (const auto& key : documented_table_keys(kSource / "docs/estimation/firefighter.md", "## Parameters")) {
    if (key.rfind("filter.", 0) == 0) documented.insert("firefighter." + key);
  }
  YamlReader::KeyRecorder recorder;
  // Every shipped and test mission: together they hold every list (victims, rescuers, sectors).
  std::vector<fs::path> files = yaml_files(kSource / "config/missions");
  for (const auto& f : yaml_files(kSource / "tests/integration/mission")) files.push_back(f);
  for (const auto& f : files) load_mission_config(f.string());
  // A mission's building.plan is a floor plan: its keys are FloorPlanKeysDocumented...'s.
  std::set<std::string> plan_keys;
  {
    YamlReader::KeyRecorder plan_recorder;
    for (const auto& f : yaml_files(kSource / "config/buildings")) load_floor_plan(f.string());
    plan_keys = plan_recorder.keys();
  }
  std::set<std::string> mission_keys;
  for (const auto& key : recorder.keys()) {
    if (plan_keys.count(key) == 0) mission_keys.insert(key);
  }
  const auto accepted = leaves(mission_keys);
  EXPECT_EQ(difference(documented, accepted), "") << "documented but refused as unknown by the mission loader";
  EXPECT_EQ(difference(accepted, documented), "") << "read by the mission loader but not documented";
}

TEST(ConfigDocs, EvaluationKeysDocumentedAreExactlyThoseTheLoaderReads) {
  std::set<std::string> documented = documented_model_keys();
  ASSERT_GT(documented.size(), 40U) << "docs/estimation/avalanche.md: parameter table not found";
  // The baselines' sections (particle:, grid:) are the evaluation's alone.
  const auto baselines = documented_table_keys(kSource / "docs/estimation/baselines.md", "## Parameters");
  ASSERT_GT(baselines.size(), 8U) << "docs/estimation/baselines.md: parameter table not found";
  documented.insert(baselines.begin(), baselines.end());
  YamlReader::KeyRecorder recorder;
  avalanche::EvaluationSetup setup;
  eval::load_avalanche_config((kSource / "config/eval/avalanche.yaml").string(), setup);
  const auto accepted = leaves(recorder.keys());
  EXPECT_EQ(difference(documented, accepted), "") << "documented but refused as unknown by the evaluation loader";
  EXPECT_EQ(difference(accepted, documented), "") << "read by the evaluation loader but not documented";
}

TEST(ConfigDocs, FirefighterEvaluationKeysDocumentedAreExactlyThoseTheLoaderReads) {
  const auto documented = documented_table_keys(kSource / "docs/estimation/firefighter.md", "## Parameters");
  ASSERT_GT(documented.size(), 40U) << "docs/estimation/firefighter.md: parameter table not found";
  YamlReader::KeyRecorder recorder;
  firefighter::FirefighterEvalConfig config;
  eval::load_firefighter_config((kSource / "config/eval/firefighter.yaml").string(), config);
  const auto accepted = leaves(recorder.keys());
  EXPECT_EQ(difference(documented, accepted), "") << "documented but refused by the firefighter loader";
  EXPECT_EQ(difference(accepted, documented), "") << "read by the firefighter loader but not documented";
}

TEST(ConfigDocs, FloorPlanKeysDocumentedAreExactlyThoseTheLoaderReads) {
  const auto documented = documented_table_keys(kSource / "docs/configuration.md", "## Floor plans");
  ASSERT_GT(documented.size(), 20U) << "docs/configuration.md: floor-plan table not found";
  YamlReader::KeyRecorder recorder;
  for (const auto& f : yaml_files(kSource / "config/buildings")) load_floor_plan(f.string());
  const auto accepted = leaves(recorder.keys());
  EXPECT_EQ(difference(documented, accepted), "") << "documented but refused by the floor-plan loader";
  EXPECT_EQ(difference(accepted, documented), "") << "read by the floor-plan loader but not documented";
}

}  // namespace
}  // namespace sarloc::app
