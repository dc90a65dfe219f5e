// Exclusive scan as a reusable plan: the launch shape and block-sums buffer are made once and the scan
// recorded as often as needed (the radix sort scans its histogram once per digit pass).
#pragma once
#include <cstdint>

#include "launch_shape.h"
#include "megavox/device.h"

namespace mv {

struct ScanPlan {
  uint32_t n = 0;
  BlockShape shape{};
  Buffer sums;  // shape.blocks + 1 values
};

// n at most kMaxDeviceItems (mv::Error beyond).
ScanPlan plan_scan(Device& dev, uint64_t n);

// dst[i] = src[0] + ... + src[i-1], dst[n] = total; src may equal dst. Recorded, ends with a barrier.
void record_scan(Device& dev, ScanPlan& plan, const Buffer& src, Buffer& dst);

}  // namespace mv
