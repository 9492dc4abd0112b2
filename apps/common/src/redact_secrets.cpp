#include "sarloc/app/redact_secrets.hpp"

#include <regex>

namespace sarloc::app {

std::string redact_secrets(const std::string& yaml_text) {
  // A key at a line's start or after '{' or ',' (flow style), its value quoted or plain up to
  // the next ',', '}', comment or line end.
  static const std::regex secret(R"(((?:^|[{,])[ \t]*["']?(?:[a-z_]*token|password|secret|private_key)["']?[ \t]*:[ \t]*)("[^"\n]*"|'[^'\n]*'|[^,}#\n]*[^,}#\n \t]))",
                                 std::regex::multiline);
  return std::regex_replace(yaml_text, secret, "$1\"(redacted)\"");
}

}  // namespace sarloc::app
