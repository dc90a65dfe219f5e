#include "omicron_representatives.h"

#include <algorithm>

#include "common/points.h"
#include "megavox/error.h"
#include "omicron_representatives_host.h"
#include "primitives/chunking.h"

namespace mv::points {

namespace {

// Candidates per dispatch: codes, bounds and positions of 8M candidates stay well inside every binding limit.
constexpr uint64_t kBatchCandidates = uint64_t{1} << 23;

// One dispatch pair over parents [g0, g1), whose candidates start at codes[base].
void select_batch(Device& dev, std::span<const uint64_t> codes, std::span<const uint32_t> bounds, uint32_t g0,
                  uint32_t g1, uint32_t cell_bits, uint32_t cap, RepSelection& out) {
  const uint32_t groups = g1 - g0;
  const uint32_t base = bounds[g0];
  const uint64_t m = bounds[g1] - base;
  std::vector<uint32_t> local_bounds(groups + 1);
  for (uint32_t g = 0; g <= groups; ++g) local_bounds[g] = bounds[g0 + g] - base;
  Buffer cb = dev.alloc(m * 8, "representative candidates");
  Buffer bb = dev.alloc(uint64_t{groups + 1} * 4, "representative groups");
  Buffer cells = dev.alloc(uint64_t{groups} * 4, "representative cells");
  Buffer kept = dev.alloc(uint64_t{groups + 1} * 4, "representative counts");
  dev.upload(cb, codes.data() + base, m * 8);
  dev.upload(bb, local_bounds.data(), local_bounds.size() * 4);
  MvPointParams p{};
  p.n = groups;
  p.cell_bits = cell_bits;
  p.cap = cap;
  // One work-item per parent: a loop-capped device then runs one parent's candidates per loop.
  const uint32_t local = 64;
  const uint32_t wg = static_cast<uint32_t>((uint64_t{groups} + local - 1) / local);
  if (wg > dev.info().max_groups) throw Error("points: " + std::to_string(groups) + " parents in one dispatch");
  dev.dispatch(dev.kernel(KernelId::omicron_rep_count), wg, local, {&cb, &bb, &cells, &kept}, p);
  dev.barrier();
  exclusive_scan(dev, kept, kept, groups);
  dev.barrier();
  uint32_t total = 0;
  dev.download(kept, &total, 4, uint64_t{groups} * 4);
  Buffer ob = dev.alloc(std::max<uint64_t>(total, 1) * 4, "representatives");
  dev.dispatch(dev.kernel(KernelId::omicron_rep_select), wg, local, {&cb, &bb, &cells, &kept, &ob}, p);
  dev.barrier();
  std::vector<uint32_t> offsets(groups + 1);
  dev.download(kept, offsets.data(), offsets.size() * 4);
  const size_t at = out.positions.size();
  out.positions.resize(at + total);
  if (total) dev.download(ob, out.positions.data() + at, uint64_t{total} * 4);
  for (size_t i = at; i < out.positions.size(); ++i) out.positions[i] += base;
  for (uint32_t g = 1; g <= groups; ++g) out.offsets.push_back(at + offsets[g]);
}

}  // namespace

RepSelection select_representatives(Device& dev, std::span<const uint64_t> codes, std::span<const uint32_t> bounds,
                                    uint32_t cell_bits, uint32_t cap) {
  RepSelection out;
  out.offsets.push_back(0);
  if (bounds.size() < 2) return out;
  const uint32_t groups = static_cast<uint32_t>(bounds.size() - 1);
  // A loop-capped device (lavapipe ends a loop after 65535 iterations) cannot walk a larger parent in one loop.
  const uint64_t loop_cap = dev.info().max_loop_iterations;
  auto too_long = [&](uint32_t g) { return loop_cap != 0 && uint64_t{bounds[g + 1] - bounds[g]} + 1 >= loop_cap; };
  // Per candidate: its code (8 bytes) and up to one position out (4); per parent a few words more.
  const uint64_t batch = std::min(kBatchCandidates, detail::device_chunk(dev, "representatives", 16, 8));
  uint32_t g = 0;
  while (g < groups) {
    if (too_long(g)) {
      std::vector<uint32_t> pos =
          representatives_on_host(codes.subspan(bounds[g], bounds[g + 1] - bounds[g]), cell_bits, cap);
      for (uint32_t p : pos) out.positions.push_back(p + bounds[g]);
      out.offsets.push_back(out.positions.size());
      ++out.host_groups;
      ++g;
      continue;
    }
    uint32_t end = g + 1;
    while (end < groups && !too_long(end) && uint64_t{bounds[end + 1] - bounds[g]} <= batch) ++end;
    select_batch(dev, codes, bounds, g, end, cell_bits, cap, out);
    g = end;
  }
  return out;
}
}  // namespace mv::points
