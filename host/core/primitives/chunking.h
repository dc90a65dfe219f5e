// Counts past what one device call of a primitive covers: the check every device-buffer entry makes, and the
// host-driven chunked paths (host arrays of any length over device-sized chunks) with the chunk size as a
// parameter: the public overloads take it from the device's memory, tests shrink it to put seams anywhere.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv::detail {

// Throws mv::Error when one device call of `what` would cover more than kMaxDeviceItems items.
inline void check_device_items(const char* what, uint64_t n) {
  if (n > kMaxDeviceItems)
    throw Error(std::string(what) + ": " + std::to_string(n) + " items in one call on device buffers, over the " +
                std::to_string(kMaxDeviceItems) + " its 32-bit kernel indices reach; split the work into chunks");
}

// What the device's budget has left. Buffers released since the last wait count as used until the next one;
// with `wait` it waits first, so they do not.
uint64_t memory_left(Device& dev, bool wait);

// Items per chunk when each costs `item_bytes` of device memory, `largest_bytes` of them in its largest buffer:
// half of what is left of the budget (room for small buffers and fragmentation), within the largest allocation
// and kMaxDeviceItems. Waits. Throws mv::DeviceMemoryError when not even one item fits.
uint64_t device_chunk(Device& dev, const char* what, uint64_t item_bytes, uint64_t largest_bytes);

uint64_t exclusive_scan_chunked(Device& dev, std::span<const uint32_t> in, std::span<uint64_t> out, uint64_t chunk);
uint64_t unique_sorted_chunked(Device& dev, std::span<const uint64_t> keys, std::span<uint64_t> out, uint64_t chunk);
// Runs of `chunk` keys sorted on the device one after the other, then merged on the host.
SortReport radix_sort_chunked(Device& dev, std::vector<uint32_t>& keys, std::vector<uint32_t>* values,
                              SortStrategy strategy, uint64_t chunk);
SortReport radix_sort_chunked(Device& dev, std::vector<uint64_t>& keys, std::vector<uint32_t>* values,
                              SortStrategy strategy, uint64_t chunk);

}  // namespace mv::detail
