#pragma once
#include "sarloc/core/common/errors.hpp"

namespace sarloc::dds {

/// A DDS entity could not be created or an XML profile could not be loaded.
class DdsError : public sarloc::Error {
 public:
  using sarloc::Error::Error;
};

}  // namespace sarloc::dds
