#include "common/scan.h"

#include <algorithm>

#include "primitives/chunking.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "primitives/scan_plan.h"

namespace mv {

static_assert(kMaxDeviceItems == MV_MAX_ITEMS);

ScanPlan plan_scan(Device& dev, uint64_t n, bool wide) {
  detail::check_device_items("exclusive_scan", n);
  ScanPlan plan;
  plan.n = static_cast<uint32_t>(n);
  plan.wide = wide;
  plan.shape = block_shape(dev.info(), n);
  const uint32_t cap = dev.info().max_loop_iterations;
  if (cap && plan.shape.blocks >= cap)
    throw Error("exclusive_scan: " + std::to_string(n) + " values need " + std::to_string(plan.shape.blocks) +
                " blocks, more than one loop may run on " + dev.info().name);
  plan.sums = dev.alloc((uint64_t{plan.shape.blocks} + 1) * 8, "scan block sums");
  return plan;
}

void record_scan(Device& dev, ScanPlan& plan, const Buffer& src, Buffer& dst, uint64_t start) {
  const uint64_t n = plan.n;
  const uint64_t out_bytes = plan.wide ? 8 : 4;
  if (src.bytes() < n * 4 || dst.bytes() < (n + 1) * out_bytes)
    throw Error("exclusive_scan: buffers too small for " + std::to_string(n) + " values");
  const BlockShape& s = plan.shape;
  const auto lo = static_cast<uint32_t>(start), hi = static_cast<uint32_t>(start >> 32);
  MvScanParams p{plan.n, s.blocks, s.block_size, plan.wide ? 1u : 0u, lo, hi};
  // Where a group's items run side by side (groups of more than one), a group sums each block, its items reading
  // consecutive values; elsewhere (PoCL's groups of one) each item walks a block alone.
  const bool grouped = s.local_size > 1 && s.local_size <= MV_SCAN_GROUP;
  const uint32_t groups = grouped ? s.blocks : s.groups;
  dev.dispatch(dev.kernel(grouped ? KernelId::scan_reduce_group : KernelId::scan_reduce), groups, s.local_size,
               {&src, &plan.sums}, p);
  dev.barrier();
  MvScanParams small{s.blocks, 1, s.blocks, 0, lo, hi};
  dev.dispatch(dev.kernel(KernelId::scan_small), 1, 1, {&plan.sums}, small);
  dev.barrier();
  dev.dispatch(dev.kernel(KernelId::scan_apply), s.groups, s.local_size, {&src, &dst, &plan.sums}, p);
  dev.copy(plan.sums, dst, out_bytes, uint64_t{s.blocks} * 8, n * out_bytes);  // the total (its low word)
  dev.barrier();
}

void exclusive_scan(Device& dev, const Buffer& src, Buffer& dst, uint64_t n) {
  ScanPlan plan = plan_scan(dev, n);
  record_scan(dev, plan, src, dst);
}

void exclusive_scan64(Device& dev, const Buffer& src, Buffer& dst, uint64_t n, uint64_t start) {
  if (&src == &dst) throw Error("exclusive_scan64: src and dst must be different buffers");
  ScanPlan plan = plan_scan(dev, n, true);
  record_scan(dev, plan, src, dst, start);
}

uint64_t exclusive_scan(Device& dev, std::span<const uint32_t> in, std::span<uint64_t> out) {
  // per value: 4 bytes in and 8 out on the device
  return detail::exclusive_scan_chunked(dev, in, out, detail::device_chunk(dev, "exclusive_scan", 12, 8));
}

namespace detail {

uint64_t memory_left(Device& dev, bool wait) {
  if (wait) dev.finish();
  return dev.memory_budget() - std::min(dev.memory_used(), dev.memory_budget());
}

uint64_t device_chunk(Device& dev, const char* what, uint64_t item_bytes, uint64_t largest_bytes) {
  const uint64_t left = memory_left(dev, true);
  const uint64_t chunk = std::min({left / 2 / item_bytes, dev.info().max_allocation_bytes / largest_bytes,
                                   kMaxDeviceItems});
  if (chunk == 0)
    throw DeviceMemoryError(std::string(what) + ": no device memory left for a chunk (" +
                            format_bytes(item_bytes) + " per item twice over; " + format_bytes(left) +
                            " of the budget " + format_bytes(dev.memory_budget()) + " left)");
  return chunk;
}

uint64_t exclusive_scan_chunked(Device& dev, std::span<const uint32_t> in, std::span<uint64_t> out, uint64_t chunk) {
  const uint64_t n = in.size();
  if (out.size() != n + 1)
    throw Error("exclusive_scan: the output holds " + std::to_string(out.size()) + " values, not n + 1 = " +
                std::to_string(n + 1));
  chunk = std::clamp<uint64_t>(chunk, 1, std::max<uint64_t>(n, 1));
  Buffer src = dev.alloc(chunk * 4, "scan chunk");
  Buffer dst = dev.alloc((chunk + 1) * 8, "scan chunk sums");
  out[0] = 0;
  for (uint64_t first = 0; first < n; first += chunk) {
    const uint64_t m = std::min(chunk, n - first);
    dev.upload(src, in.data() + first, m * 4);
    exclusive_scan64(dev, src, dst, m, out[first]);  // from the running total of the chunks before
    dev.download(dst, out.data() + first, (m + 1) * 8);
  }
  return out[n];
}

}  // namespace detail

}  // namespace mv
