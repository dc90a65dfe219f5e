#include "omicron_representatives.h"

#include <algorithm>

#include "common/omicron.h"
#include "megavox/error.h"
#include "megavox/segmented.h"
#include "primitives/chunking.h"

namespace mv::points {

namespace {

// Candidates per batch: codes and distances of 8M candidates (64 MiB each) stay inside every binding limit.
constexpr uint64_t kBatchCandidates = uint64_t{1} << 23;
// Device bytes per candidate: code, distance, cell heads and numbers, and per cell (at most one per candidate)
// its start, nearest candidate, keep flag, position and output.
constexpr uint64_t kBytesPerCandidate = 8 + 8 + 4 + 4 + 5 * 4;
constexpr uint32_t kRepLocal = 64;

// Parents [g0, g1), whose candidates start at codes[bounds[g0]]: cells by a segmentation of the codes, each
// cell's nearest candidate by a segmented arg-min, the kept cells by a scan of their flags.
void select_batch(Device& dev, std::span<const uint64_t> codes, std::span<const uint32_t> bounds, uint32_t g0,
                  uint32_t g1, uint32_t cell_bits, uint32_t cap, RepSelection& out) {
  const uint32_t groups = g1 - g0;
  const uint32_t base = bounds[g0];
  const uint64_t m = bounds[g1] - base;
  std::vector<uint32_t> local_bounds(groups + 1);
  for (uint32_t g = 0; g <= groups; ++g) local_bounds[g] = bounds[g0 + g] - base;
  Buffer cb = dev.alloc(m * 8, "representative candidates");
  Buffer bb = dev.alloc(uint64_t{groups + 1} * 4, "representative parents");
  dev.upload(cb, codes.data() + base, m * 8);
  dev.upload(bb, local_bounds.data(), local_bounds.size() * 4);
  dev.barrier();
  MvRepParams p{};
  p.n = static_cast<uint32_t>(m);
  p.groups = groups;
  p.cell_bits = cell_bits;
  p.cap = cap;
  Buffer heads = dev.alloc(m * 4, "representative cell heads");
  segment_heads(dev, cb, heads, m, cell_bits);
  dev.dispatch(dev.kernel(KernelId::omicron_rep_heads), dev.groups_for(groups, kRepLocal), kRepLocal, {&bb, &heads}, p);
  dev.barrier();
  Segmentation cells = segment_by_heads(dev, heads, m);
  p.cells = static_cast<uint32_t>(cells.count);
  Buffer dist = dev.alloc(m * 8, "representative distances");
  dev.dispatch(dev.kernel(KernelId::omicron_rep_distance), dev.groups_for(m, kRepLocal), kRepLocal, {&cb, &dist}, p);
  dev.barrier();
  Buffer nearest = dev.alloc(cells.count * 4, "representative nearest");
  segmented_argmin(dev, cells, dist, nearest);
  Buffer keep = dev.alloc(cells.count * 4, "representative keep flags");
  Buffer pos = dev.alloc((cells.count + 1) * 4, "representative positions");
  const uint32_t cell_groups = dev.groups_for(cells.count, kRepLocal);
  dev.dispatch(dev.kernel(KernelId::omicron_rep_keep), cell_groups, kRepLocal, {&bb, &cells.e, &cells.starts, &keep},
               p);
  dev.barrier();
  exclusive_scan(dev, keep, pos, cells.count);  // pos[c]: kept cell c's output position; pos[cells]: the total
  Buffer offsets = dev.alloc(uint64_t{groups + 1} * 4, "representative offsets");
  dev.dispatch(dev.kernel(KernelId::omicron_rep_offsets), dev.groups_for(uint64_t{groups} + 1, kRepLocal), kRepLocal,
               {&bb, &cells.e, &pos, &offsets}, p);
  dev.barrier();
  std::vector<uint32_t> local_offsets(groups + 1);
  dev.download(offsets, local_offsets.data(), local_offsets.size() * 4);
  const uint32_t total = local_offsets[groups];
  Buffer positions = dev.alloc(std::max<uint64_t>(total, 1) * 4, "representatives");
  dev.dispatch(dev.kernel(KernelId::omicron_rep_compact), cell_groups, kRepLocal, {&keep, &pos, &nearest, &positions},
               p);
  dev.barrier();
  const size_t at = out.positions.size();
  out.positions.resize(at + total);
  if (total) dev.download(positions, out.positions.data() + at, uint64_t{total} * 4);
  for (size_t i = at; i < out.positions.size(); ++i) out.positions[i] += base;
  for (uint32_t g = 1; g <= groups; ++g) out.offsets.push_back(at + local_offsets[g]);
}

}  // namespace

RepSelection select_representatives(Device& dev, std::span<const uint64_t> codes, std::span<const uint32_t> bounds,
                                    uint32_t cell_bits, uint32_t cap) {
  RepSelection out;
  out.offsets.push_back(0);
  if (bounds.size() < 2) return out;
  const uint32_t groups = static_cast<uint32_t>(bounds.size() - 1);
  const uint64_t batch =
      std::min(kBatchCandidates, detail::device_chunk(dev, "representatives", kBytesPerCandidate, 8));
  uint32_t g = 0;
  while (g < groups) {
    // Whole parents per batch; a parent larger than a batch has one to itself, whose buffers the device must
    // hold at once (dev.alloc says so clearly where it cannot).
    uint32_t end = g + 1;
    while (end < groups && uint64_t{bounds[end + 1] - bounds[g]} <= batch) ++end;
    if (bounds[end] == bounds[g]) {  // parents without candidates keep nothing
      for (uint32_t e = g; e < end; ++e) out.offsets.push_back(out.positions.size());
    } else {
      select_batch(dev, codes, bounds, g, end, cell_bits, cap, out);
    }
    g = end;
  }
  return out;
}
}  // namespace mv::points
