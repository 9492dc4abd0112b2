// Each DDS test has a domain of its own (tests/support/dds_test_domains.hpp): ctest -j runs the
// tests of one file at once, and two on one domain talk across each other. Two EstimateWriter
// tests once shared one: the first waited for the second's stopped recorder and failed in CI.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Files whose tests ctest runs one at a time (RUN_SERIAL in their CMakeLists.txt).
bool runs_serially(const fs::path& path) {
  const std::string p = path.generic_string();
  return p.find("/tests/integration/mission/") != std::string::npos || p.find("/tests/accuracy/") != std::string::npos;
}

TEST(DdsTestDomains, NoTwoTestsThatMayRunAtOnceShareADomain) {
  const std::regex test_head(R"(^TEST(_F|_P)?\((\w+),\s*(\w+)\))");
  const std::regex domain(R"(\bkDomain\w+(\s*\+\s*\d+)?)");
  std::map<std::string, std::set<std::string>> tests_of;  // domain as written -> tests
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(SARLOC_SOURCE_DIR) / "tests")) {
    if (entry.path().extension() != ".cpp" || runs_serially(entry.path()) ||
        entry.path().generic_string().find("/node_modules/") != std::string::npos)
      continue;
    ++files;
    std::istringstream lines(read_file(entry.path()));
    std::string line, current;  // the test whose body the line is in ("" outside a test)
    while (std::getline(lines, line)) {
      std::smatch head;
      if (std::regex_search(line, head, test_head)) current = head[2].str() + "." + head[3].str();
      if (current.empty()) continue;
      for (std::sregex_iterator it(line.begin(), line.end(), domain), end; it != end; ++it) {
        std::string name = it->str();
        name.erase(std::remove_if(name.begin(), name.end(), ::isspace), name.end());
        tests_of[name].insert(current);
      }
      if (line == "}") current.clear();  // a test's body ends at a brace in the first column
    }
  }
  ASSERT_GT(files, 50u) << "the test sources were not found under " << SARLOC_SOURCE_DIR;
  ASSERT_GT(tests_of.size(), 20u) << "no domains found: the pattern no longer matches the tests";
  for (const auto& [name, tests] : tests_of) {
    std::string list;
    for (const auto& t : tests) list += " " + t;
    EXPECT_EQ(tests.size(), 1u) << name << " is used by" << list;
  }
}

TEST(DdsTestDomains, EveryDomainIdIsListedOnce) {
  const std::string header = read_file(fs::path(SARLOC_SOURCE_DIR) / "tests/support/dds_test_domains.hpp");
  const std::regex entry(R"((kDomain\w+)\s*=\s*(\d+))");
  std::map<int, std::string> names_of;
  for (std::sregex_iterator it(header.begin(), header.end(), entry), end; it != end; ++it) {
    const int id = std::stoi((*it)[2].str());
    const auto [where, inserted] = names_of.emplace(id, (*it)[1].str());
    EXPECT_TRUE(inserted) << "domain " << id << ": " << where->second << " and " << (*it)[1].str();
  }
  EXPECT_GT(names_of.size(), 50u);
}

}  // namespace
