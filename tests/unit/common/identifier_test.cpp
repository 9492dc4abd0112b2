// The one identifier rule (sarloc/core/common/identifier.hpp), and error messages that show any
// bytes printably.
#include "sarloc/core/common/identifier.hpp"

#include <gtest/gtest.h>

#include <string>

#include "sarloc/core/common/errors.hpp"

namespace sarloc {
namespace {

TEST(Identifier, LettersDigitsAndThreeMarksUpTo64) {
  for (const char* id : {"r1", "team-north", "ff_2", "engine.7", "A", "0"}) EXPECT_TRUE(is_identifier(id)) << id;
  EXPECT_TRUE(is_identifier(std::string(64, 'x')));
  EXPECT_FALSE(is_identifier(std::string(65, 'x')));
  EXPECT_FALSE(is_identifier(""));
  for (const char* id : {"r 1", "<img src=x onerror=alert(1)>", "\"><script>", "a/b", "../x", "r1\n", "é", "bad\xff\xfeid"}) {
    EXPECT_FALSE(is_identifier(id)) << printable_excerpt(id);
  }
}

TEST(Identifier, ErrorsNameTheFieldAndShowTheBytesPrintably) {
  try {
    check_identifier("bad\xff\xfeid", "responder_position.responder_id");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "responder_position.responder_id = 'bad\\xFF\\xFEid': not an identifier (1-64 of A-Z a-z 0-9 _ . -)");
  }
  EXPECT_NO_THROW(check_identifier("", "team_id", true)) << "an optional id may be empty";
  EXPECT_THROW(check_identifier("", "team_id"), InputError);
  EXPECT_EQ(printable_excerpt(std::string(100, 'a')), "'" + std::string(40, 'a') + "' (+60 bytes)");
  EXPECT_EQ(identifier_problem("r1", "x"), "");
}

}  // namespace
}  // namespace sarloc
