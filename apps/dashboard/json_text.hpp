#pragma once
// Every JSON the dashboard sends goes out through json_text(): bytes that are not UTF-8 become
// U+FFFD instead of an exception. Ids are checked at the DDS boundary already (to_core); this
// is the second wall, for any text that reaches the page some other way (a plan's name, a
// recording made by an older build). A throwing dump() in the event stream once ended the process.
#include <nlohmann/json.hpp>

#include <string>

namespace sarloc::dashboard {

inline std::string json_text(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace sarloc::dashboard
