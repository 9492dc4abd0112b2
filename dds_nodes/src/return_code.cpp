#include "sarloc/dds/return_code.hpp"

namespace sarloc::dds {

const char* return_code_name(const eprosima::fastrtps::types::ReturnCode_t& code) {
  using R = eprosima::fastrtps::types::ReturnCode_t;
  switch (code()) {
    case R::RETCODE_OK:
      return "RETCODE_OK";
    case R::RETCODE_ERROR:
      return "RETCODE_ERROR";
    case R::RETCODE_UNSUPPORTED:
      return "RETCODE_UNSUPPORTED";
    case R::RETCODE_BAD_PARAMETER:
      return "RETCODE_BAD_PARAMETER";
    case R::RETCODE_PRECONDITION_NOT_MET:
      return "RETCODE_PRECONDITION_NOT_MET";
    case R::RETCODE_OUT_OF_RESOURCES:
      return "RETCODE_OUT_OF_RESOURCES";
    case R::RETCODE_NOT_ENABLED:
      return "RETCODE_NOT_ENABLED";
    case R::RETCODE_IMMUTABLE_POLICY:
      return "RETCODE_IMMUTABLE_POLICY";
    case R::RETCODE_INCONSISTENT_POLICY:
      return "RETCODE_INCONSISTENT_POLICY";
    case R::RETCODE_ALREADY_DELETED:
      return "RETCODE_ALREADY_DELETED";
    case R::RETCODE_TIMEOUT:
      return "RETCODE_TIMEOUT";
    case R::RETCODE_NO_DATA:
      return "RETCODE_NO_DATA";
    case R::RETCODE_ILLEGAL_OPERATION:
      return "RETCODE_ILLEGAL_OPERATION";
    case R::RETCODE_NOT_ALLOWED_BY_SECURITY:
      return "RETCODE_NOT_ALLOWED_BY_SECURITY";
    default:
      return "RETCODE_UNKNOWN";
  }
}

}  // namespace sarloc::dds
