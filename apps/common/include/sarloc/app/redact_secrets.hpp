#pragma once
// Secrets never go into a recording or a log: a mission file's text is stored in every
// recording (sarloc-record --meta-file), and `strings REC.mcap | grep token` found the
// dashboard's operator token there (issue 59).
#include <string>

namespace sarloc::app {

/// The value of every `token` (`view_token`, ...), `password`, `secret` or `private_key` key of a YAML text, block
/// or flow style, replaced with "(redacted)"; everything else, comments and layout included,
/// left as it was. The result still loads (the placeholder is a valid token).
std::string redact_secrets(const std::string& yaml_text);

}  // namespace sarloc::app
