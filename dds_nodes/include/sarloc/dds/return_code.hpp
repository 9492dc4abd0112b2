#pragma once
// Fast DDS return codes by name, for logs that say why DDS refused something.
#include <fastrtps/types/TypesBase.h>

namespace sarloc::dds {

/// "RETCODE_TIMEOUT", "RETCODE_OUT_OF_RESOURCES", ...; "RETCODE_UNKNOWN" for a value Fast DDS 2.9 does not name.
const char* return_code_name(const eprosima::fastrtps::types::ReturnCode_t& code);

}  // namespace sarloc::dds
