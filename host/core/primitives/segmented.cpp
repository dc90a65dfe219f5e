#include "megavox/segmented.h"

#include <algorithm>

#include "common/segmented.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "primitives/chunking.h"
#include "primitives/launch_shape.h"
#include "primitives/scan_plan.h"

namespace mv {

namespace {

constexpr uint32_t kSegLocal = 64;

// A pass over n elements: contiguous blocks per work-item on CPU devices without a loop cap (PoCL runs a
// work-item's loop alone, and one element per work-item costs it a work-item's overhead per element), else
// grid-stride over work-groups of kSegLocal.
void seg_pass(Device& dev, KernelId id, uint64_t n, std::initializer_list<const Buffer*> buffers, MvSegParams p) {
  const DeviceInfo& info = dev.info();
  if (!info.massively_parallel && !info.max_loop_iterations) {
    const BlockShape s = block_shape(info, std::max<uint64_t>(n, 1));
    p.block_size = s.block_size;
    dev.dispatch(dev.kernel(id), s.groups, s.local_size, buffers, p);
  } else {
    p.block_size = 0;
    dev.dispatch(dev.kernel(id), dev.groups_for(std::max<uint64_t>(n, 1), kSegLocal), kSegLocal, buffers, p);
  }
}

MvSegParams seg_params(const Segmentation& seg) {
  MvSegParams p{};
  p.n = static_cast<uint32_t>(seg.n);
  p.count = static_cast<uint32_t>(seg.count);
  return p;
}

// P: the exclusive 64-bit scan of n 32-bit values (n + 1 entries), or of `planes` planes of n in turn.
Buffer segment_prefix(Device& dev, const Segmentation& seg, const Buffer& values, uint32_t planes = 1) {
  const uint64_t n = seg.n * planes;
  detail::check_device_items("segmented", n);
  Buffer prefix = dev.alloc((n + 1) * 8, "segmented prefix sums");
  ScanPlan plan = plan_scan(dev, n, true);
  record_scan(dev, plan, values, prefix);
  return prefix;
}

}  // namespace

Segmentation segment_by_heads(Device& dev, const Buffer& heads, uint64_t n) {
  detail::check_device_items("segmented", n);
  Segmentation seg;
  seg.n = n;
  seg.e = dev.alloc((n + 1) * 4, "segment numbers");
  if (n == 0) {
    seg.starts = dev.alloc(4, "segment starts");
    dev.fill(seg.starts, 0, 4);
    dev.fill(seg.e, 0, 4);
    return seg;
  }
  ScanPlan plan = plan_scan(dev, n);
  record_scan(dev, plan, heads, seg.e);
  // Element 0 starts a run whatever its flag says: runs before element i then count from 1.
  uint32_t total = 0, first = 0;
  dev.download(seg.e, &total, 4, n * 4);
  dev.download(heads, &first, 4);
  if (first == 0) throw Error("segmented: element 0 must start a run");
  seg.count = total;
  seg.starts = dev.alloc((seg.count + 1) * 4, "segment starts");
  MvSegParams p = seg_params(seg);
  seg_pass(dev, KernelId::seg_starts, n, {&seg.e, &seg.starts}, p);
  dev.barrier();
  return seg;
}

void segment_heads(Device& dev, const Buffer& keys, Buffer& heads, uint64_t n, uint32_t shift) {
  detail::check_device_items("segmented", n);
  MvSegParams p{};
  p.n = static_cast<uint32_t>(n);
  p.shift = shift;
  if (n) seg_pass(dev, KernelId::seg_heads, n, {&keys, &heads}, p);
  dev.barrier();
}

Segmentation segment_by_key(Device& dev, const Buffer& keys, uint64_t n, uint32_t shift) {
  Buffer heads = dev.alloc(std::max<uint64_t>(n, 1) * 4, "segment heads");
  segment_heads(dev, keys, heads, n, shift);
  return segment_by_heads(dev, heads, n);
}

uint64_t select_flagged(Device& dev, const Buffer& flags, Buffer& positions, uint64_t n) {
  detail::check_device_items("select_flagged", n);
  Buffer e = dev.alloc((n + 1) * 4, "flag positions");
  uint32_t count = 0;
  if (n) {
    ScanPlan plan = plan_scan(dev, n);
    record_scan(dev, plan, flags, e);
    dev.download(e, &count, 4, n * 4);
  } else {
    dev.fill(e, 0, 4);
  }
  // a flagged element starts a one-element run, so the runs' starts are the flagged positions
  Segmentation seg;
  seg.n = n;
  seg.count = count;
  MvSegParams p = seg_params(seg);
  seg_pass(dev, KernelId::seg_starts, n, {&e, &positions}, p);
  dev.barrier();
  return count;
}

void segmented_sum(Device& dev, const Segmentation& seg, const Buffer& values, Buffer& sums, uint32_t planes) {
  if (seg.count == 0 || planes == 0) return;
  Buffer prefix = segment_prefix(dev, seg, values, planes);
  MvSegParams p = seg_params(seg);
  p.planes = planes;
  dev.dispatch(dev.kernel(KernelId::seg_sum), dev.groups_for(seg.count, kSegLocal), kSegLocal,
               {&prefix, &seg.starts, &sums}, p);
  dev.barrier();
}

void segmented_exclusive_scan(Device& dev, const Segmentation& seg, const Buffer& values, Buffer& out) {
  if (seg.n == 0) return;
  Buffer prefix = segment_prefix(dev, seg, values);
  MvSegParams p = seg_params(seg);
  dev.dispatch(dev.kernel(KernelId::seg_scan), dev.groups_for(seg.n, kSegLocal), kSegLocal,
               {&prefix, &seg.e, &seg.starts, &out}, p);
  dev.barrier();
}

void segmented_argmin(Device& dev, const Segmentation& seg, const Buffer& values, Buffer& out) {
  if (seg.n == 0) return;
  // Small blocks on a GPU (every block is one work-item), CPU devices' few long ones otherwise.
  const BlockShape s = block_shape(dev.info(), seg.n, dev.info().massively_parallel ? 256 : 4096);
  const uint32_t cap = dev.info().max_loop_iterations;
  if (cap && s.blocks >= cap)
    throw Error("segmented_argmin: " + std::to_string(seg.n) + " values need " + std::to_string(s.blocks) +
                " blocks, more than one loop may run on " + dev.info().name);
  MvSegParams p = seg_params(seg);
  p.blocks = s.blocks;
  p.block_size = s.block_size;
  Buffer agg = dev.alloc(uint64_t{s.blocks} * 16, "segmented arg-min carries");
  dev.dispatch(dev.kernel(KernelId::seg_argmin_reduce), s.groups, s.local_size, {&values, &seg.e, &agg}, p);
  dev.barrier();
  dev.dispatch(dev.kernel(KernelId::seg_argmin_small), 1, 1, {&agg}, p);
  dev.barrier();
  dev.dispatch(dev.kernel(KernelId::seg_argmin_apply), s.groups, s.local_size, {&values, &seg.e, &agg, &out}, p);
  dev.barrier();
}

}  // namespace mv
