#include "sarloc/app/yaml_reader.hpp"

#include <gtest/gtest.h>

namespace sarloc::app {
namespace {

// The message must name the key path and the value, or the user cannot fix the file.
void expect_config_error(const std::function<void()>& f, const std::string& expected_part) {
  try {
    f();
    FAIL() << "expected ConfigError containing '" << expected_part << "'";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(expected_part), std::string::npos) << e.what();
  }
}

TEST(YamlReader, ReadsTypedValuesAndKeepsDefaultsForAbsentKeys) {
  auto yaml = YamlReader::from_string("sog:\n  components: 1700\n  prune: 12.5\n  merge: true\n  name: x\n", "t.yaml");
  auto sog = yaml.child("sog");
  unsigned components = 0;
  double prune = 0.0;
  bool merge = false;
  std::string name;
  int absent = 42;
  sog.read("components", components);
  sog.read("prune", prune);
  sog.read("merge", merge);
  sog.read("name", name);
  sog.read("absent", absent);
  EXPECT_EQ(components, 1700U);
  EXPECT_EQ(prune, 12.5);
  EXPECT_TRUE(merge);
  EXPECT_EQ(name, "x");
  EXPECT_EQ(absent, 42);
  EXPECT_NO_THROW(sog.expect_done());
  EXPECT_NO_THROW(yaml.expect_done());
}

TEST(YamlReader, UnknownKeyIsAnErrorNamingItsPath) {
  auto yaml = YamlReader::from_string("sog:\n  components: 10\n  componets: 12\n", "t.yaml");
  auto sog = yaml.child("sog");
  unsigned components = 0;
  sog.read("components", components);
  expect_config_error([&] { sog.expect_done(); }, "sog.componets");
}

TEST(YamlReader, WrongTypeNamesKeyAndValue) {
  auto yaml = YamlReader::from_string("a: abc\nb: 1.5\nc: -3\nd: .nan\ne: [1, 2]\n", "t.yaml");
  double a = 0;
  int b = 0;
  unsigned c = 0;
  double d = 0;
  Eigen::Vector3d e;
  expect_config_error([&] { yaml.read("a", a); }, "a = 'abc': expected a finite number");
  expect_config_error([&] { yaml.read("b", b); }, "b = '1.5': expected an integer");
  expect_config_error([&] { yaml.read("c", c); }, "c = '-3': expected a non-negative integer");
  expect_config_error([&] { yaml.read("d", d); }, "d = '.nan'");
  expect_config_error([&] { yaml.read("e", e); }, "e has 2 numbers");
}

TEST(YamlReader, MissingRequiredKeyIsNamed) {
  auto yaml = YamlReader::from_string("x: 1\n", "t.yaml");
  auto rescuer = yaml.child("rescuer");
  std::string id;
  expect_config_error([&] { rescuer.require("id", id); }, "rescuer.id is required");
}

TEST(YamlReader, MalformedYamlAndMissingFileAreConfigErrors) {
  expect_config_error([] { (void)YamlReader::from_string("a: [1, 2\n", "bad.yaml"); }, "bad.yaml: not valid YAML");
  expect_config_error([] { (void)YamlReader::from_file("/nonexistent/x.yaml"); }, "cannot open");
  expect_config_error([] { (void)YamlReader::from_string("- 1\n- 2\n", "list.yaml"); }, "top level must be a map");
}

TEST(YamlReader, ListsOfMapsCarryTheirIndexInMessages) {
  auto yaml = YamlReader::from_string("victims:\n  - {x: 1}\n  - {x: oops}\n", "m.yaml");
  auto victims = yaml.child_list("victims");
  ASSERT_EQ(victims.size(), 2U);
  double x = 0;
  victims[0].read("x", x);
  EXPECT_EQ(x, 1.0);
  expect_config_error([&] { victims[1].read("x", x); }, "victims[1].x = 'oops'");
}

}  // namespace
}  // namespace sarloc::app
