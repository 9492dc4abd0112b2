#pragma once
// sarloc's IDL as text, for the schemas of recordings (MCAP schema encoding `omgidl`: one
// self-contained IDL text per type, with no #include).
#include <string>

namespace sarloc::dds {

/// The text of `idl_file` (e.g. "responder.idl") with every file it includes placed before it,
/// each once, and every preprocessor line (#include, #ifndef, #define, #endif) removed.
/// Throws DdsError for a file that is not part of sarloc's IDL.
std::string self_contained_idl(const std::string& idl_file);

}  // namespace sarloc::dds
