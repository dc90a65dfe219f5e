#include "common/unique.h"

#include <algorithm>

#include "primitives/chunking.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "primitives/scan_plan.h"

namespace mv {

uint64_t unique_sorted(Device& dev, const Buffer& keys, Buffer& out, uint64_t n) {
  if (n == 0) return 0;
  detail::check_device_items("unique_sorted", n);
  if (keys.bytes() < n * 8 || out.bytes() < n * 8)
    throw Error("unique_sorted: buffers too small for " + std::to_string(n) + " keys");
  Buffer pos = dev.alloc((n + 1) * 4, "unique positions");
  MvUniqueParams p{static_cast<uint32_t>(n), 0};
  const uint32_t local = 64;
  dev.dispatch(dev.kernel(KernelId::unique_flags), dev.groups_for(n, local), local, {&keys, &pos}, p);
  dev.barrier();
  ScanPlan scan = plan_scan(dev, n);
  record_scan(dev, scan, pos, pos);
  dev.dispatch(dev.kernel(KernelId::unique_compact), dev.groups_for(n, local), local, {&keys, &pos, &out}, p);
  dev.barrier();
  uint32_t count = 0;  // at most n
  dev.download(pos, &count, 4, n * 4);
  return count;
}

uint64_t unique_sorted(Device& dev, std::span<const uint64_t> keys, std::span<uint64_t> out) {
  // per key: 8 bytes in, 8 out and 4 of positions on the device
  return detail::unique_sorted_chunked(dev, keys, out, detail::device_chunk(dev, "unique_sorted", 20, 8));
}

namespace detail {

uint64_t unique_sorted_chunked(Device& dev, std::span<const uint64_t> keys, std::span<uint64_t> out, uint64_t chunk) {
  const uint64_t n = keys.size();
  if (out.size() < n)
    throw Error("unique_sorted: the output holds " + std::to_string(out.size()) + " keys, fewer than the " +
                std::to_string(n) + " given");
  if (n == 0) return 0;
  chunk = std::clamp<uint64_t>(chunk, 1, n);
  Buffer kb = dev.alloc(chunk * 8, "unique chunk");
  Buffer ub = dev.alloc(chunk * 8, "unique chunk output");
  uint64_t count = 0, last = 0;
  for (uint64_t first = 0; first < n; first += chunk) {
    const uint64_t m = std::min(chunk, n - first);
    dev.upload(kb, keys.data() + first, m * 8);
    const uint64_t distinct = unique_sorted(dev, kb, ub, m);
    // A run of equal keys across the seam: the chunk starts with the last key kept. Both keys are read before
    // the download, which may overwrite them when out is keys' own storage.
    const uint64_t skip = count > 0 && keys[first] == last ? 1 : 0;
    last = keys[first + m - 1];
    if (distinct > skip) dev.download(ub, out.data() + count, (distinct - skip) * 8, skip * 8);
    count += distinct - skip;
  }
  return count;
}

}  // namespace detail

}  // namespace mv
