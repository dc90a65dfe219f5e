#include "../kernels/common/unique.h"

#include "chunking.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "scan_plan.h"

namespace mv {

uint64_t unique_sorted(Device& dev, const Buffer& keys, Buffer& out, uint64_t n) {
  if (n == 0) return 0;
  detail::check_device_items("unique_sorted", n);
  if (keys.bytes() < n * 8 || out.bytes() < n * 8)
    throw Error("unique_sorted: buffers too small for " + std::to_string(n) + " keys");
  Buffer pos = dev.alloc((n + 1) * 4, "unique positions");
  MvUniqueParams p{static_cast<uint32_t>(n), 0};
  const uint32_t local = 64;
  dev.dispatch(dev.kernel("unique_flags"), dev.groups_for(n, local), local, {&keys, &pos}, p);
  dev.barrier();
  ScanPlan scan = plan_scan(dev, n);
  record_scan(dev, scan, pos, pos);
  dev.dispatch(dev.kernel("unique_compact"), dev.groups_for(n, local), local, {&keys, &pos, &out}, p);
  dev.barrier();
  uint32_t count = 0;  // at most n
  dev.download(pos, &count, 4, n * 4);
  return count;
}

}  // namespace mv
