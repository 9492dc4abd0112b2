#include "sarloc/dds/sign_off.hpp"

#include <spdlog/spdlog.h>

namespace sarloc::dds {

bool sign_off(Writer<::sarloc::ResponderPosition>& device_position_writer, const std::string& responder_id,
              std::chrono::milliseconds timeout) {
  ::sarloc::ResponderPosition key;
  key.responder_id(responder_id);
  if (!device_position_writer.dispose(key)) {
    spdlog::error("{}: DDS refused the sign-off (disposal of the position instance)", responder_id);
    return false;
  }
  if (!device_position_writer.wait_for_acknowledgments(timeout)) {
    spdlog::warn("{}: the sign-off was not acknowledged within {} ms: incident command may report the link lost",
                 responder_id, timeout.count());
    return false;
  }
  spdlog::info("{}: signed off", responder_id);
  return true;
}

}  // namespace sarloc::dds
