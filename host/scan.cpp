#include "../kernels/common/scan.h"

#include "chunking.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "scan_plan.h"

namespace mv {

static_assert(kMaxDeviceItems == MV_MAX_ITEMS);

ScanPlan plan_scan(Device& dev, uint64_t n) {
  detail::check_device_items("exclusive_scan", n);
  ScanPlan plan;
  plan.n = static_cast<uint32_t>(n);
  plan.shape = block_shape(dev.info(), n);
  const uint32_t cap = dev.info().max_loop_iterations;
  if (cap && plan.shape.blocks >= cap)
    throw Error("exclusive_scan: " + std::to_string(n) + " values need " + std::to_string(plan.shape.blocks) +
                " blocks, more than one loop may run on " + dev.info().name);
  plan.sums = dev.alloc((uint64_t{plan.shape.blocks} + 1) * 4, "scan block sums");
  return plan;
}

void record_scan(Device& dev, ScanPlan& plan, const Buffer& src, Buffer& dst) {
  const uint64_t n = plan.n;
  if (src.bytes() < n * 4 || dst.bytes() < (n + 1) * 4)
    throw Error("exclusive_scan: buffers too small for " + std::to_string(n) + " values");
  const BlockShape& s = plan.shape;
  MvScanParams p{plan.n, s.blocks, s.block_size, 0};
  dev.dispatch(dev.kernel("scan_reduce"), s.groups, s.local_size, {&src, &plan.sums}, p);
  dev.barrier();
  MvScanParams small{s.blocks, 1, s.blocks, 0};
  dev.dispatch(dev.kernel("scan_small"), 1, 1, {&plan.sums}, small);
  dev.barrier();
  dev.dispatch(dev.kernel("scan_apply"), s.groups, s.local_size, {&src, &dst, &plan.sums}, p);
  dev.copy(plan.sums, dst, 4, uint64_t{s.blocks} * 4, n * 4);
  dev.barrier();
}

void exclusive_scan(Device& dev, const Buffer& src, Buffer& dst, uint64_t n) {
  ScanPlan plan = plan_scan(dev, n);
  record_scan(dev, plan, src, dst);
}

}  // namespace mv
