#include "../kernels/common/unique.h"

#include "megavox/error.h"
#include "megavox/primitives.h"
#include "scan_plan.h"

namespace mv {

uint32_t unique_sorted(Device& dev, const Buffer& keys, Buffer& out, uint32_t n) {
  if (n == 0) return 0;
  if (keys.bytes() < uint64_t{n} * 8 || out.bytes() < uint64_t{n} * 8)
    throw Error("unique_sorted: buffers too small for " + std::to_string(n) + " keys");
  Buffer pos = dev.alloc((uint64_t{n} + 1) * 4, "unique positions");
  MvUniqueParams p{n, 0};
  const uint32_t local = 64;
  dev.dispatch(dev.kernel(KernelId::unique_flags), dev.groups_for(n, local), local, {&keys, &pos}, p);
  dev.barrier();
  ScanPlan scan = plan_scan(dev, n);
  record_scan(dev, scan, pos, pos);
  dev.dispatch(dev.kernel(KernelId::unique_compact), dev.groups_for(n, local), local, {&keys, &pos, &out}, p);
  dev.barrier();
  uint32_t count = 0;
  dev.download(pos, &count, 4, uint64_t{n} * 4);
  return count;
}

}  // namespace mv
