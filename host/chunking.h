// Counts past what one device call of a primitive covers: the check every device-buffer entry makes.
#pragma once
#include <cstdint>
#include <string>

#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv::detail {

// Throws mv::Error when one device call of `what` would cover more than kMaxDeviceItems items.
inline void check_device_items(const char* what, uint64_t n) {
  if (n > kMaxDeviceItems)
    throw Error(std::string(what) + ": " + std::to_string(n) + " items in one call on device buffers, over the " +
                std::to_string(kMaxDeviceItems) + " its 32-bit kernel indices reach; split the work into chunks");
}

}  // namespace mv::detail
