#include "sarloc/dds/sign_off.hpp"

#include <spdlog/spdlog.h>

namespace sarloc::dds {
namespace {

// Disposes the instance whose key `key` holds, then waits for the readers' acknowledgements.
template <class T>
bool dispose_and_wait(Writer<T>& writer, const T& key, const std::string& who, std::chrono::milliseconds timeout) {
  if (!writer.dispose(key)) {
    spdlog::error("{}: DDS refused the sign-off (disposal of its {} instance)", who, TopicTraits<T>::kName);
    return false;
  }
  if (!writer.wait_for_acknowledgments(timeout)) {
    spdlog::warn("{}: the sign-off was not acknowledged within {} ms: readers may report it lost", who, timeout.count());
    return false;
  }
  spdlog::info("{}: signed off", who);
  return true;
}

}  // namespace

bool sign_off(Writer<::sarloc::ResponderPosition>& device_position_writer, const std::string& responder_id,
              std::chrono::milliseconds timeout) {
  ::sarloc::ResponderPosition key;
  key.responder_id(responder_id);
  return dispose_and_wait(device_position_writer, key, responder_id, timeout);
}

bool sign_off(Writer<::sarloc::NodeStatus>& status_writer, const std::string& node_id, std::chrono::milliseconds timeout) {
  ::sarloc::NodeStatus key;
  key.node_id(node_id);
  return dispose_and_wait(status_writer, key, node_id, timeout);
}

}  // namespace sarloc::dds
