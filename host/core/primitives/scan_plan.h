// Exclusive scan as a reusable plan: the launch shape and block-sums buffer are made once and the scan
// recorded as often as needed (the radix sort scans its histogram once per digit pass).
#pragma once
#include <cstdint>

#include "primitives/launch_shape.h"
#include "megavox/device.h"

namespace mv {

struct ScanPlan {
  uint32_t n = 0;
  bool wide = false;  // 64-bit sums out (else 32-bit, mod 2^32)
  BlockShape shape{};
  Buffer sums;  // shape.blocks + 1 64-bit values
};

// n at most kMaxDeviceItems (throws mv::Error beyond).
ScanPlan plan_scan(Device& dev, uint64_t n, bool wide = false);

// dst[i] = start + src[0] + ... + src[i-1], dst[n] = the total; src may equal dst unless the plan is wide.
// Recorded, ends with a barrier.
void record_scan(Device& dev, ScanPlan& plan, const Buffer& src, Buffer& dst, uint64_t start = 0);

}  // namespace mv
