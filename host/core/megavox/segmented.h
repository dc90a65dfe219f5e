// megavox — segmented operations on a Device: per-run work over sorted elements (a cell's points, a parent's
// cells, a voxel's fragments) spread over the elements, never one work-item per run, so a run of millions costs
// what any other run of elements does. Kernels: kernels/common/segmented.h.
//
// A Segmentation describes how n elements cut into runs: `e` holds n + 1 32-bit values, the exclusive scan of
// the head flags (e[i] = runs starting before element i, e[n] = count), and `starts` count + 1 values (the
// first element of each run, then n). Calls record work and return without waiting, except where noted; n is
// at most kMaxDeviceItems.
#pragma once
#include <cstdint>

#include "megavox/device.h"

namespace mv {

struct Segmentation {
  uint64_t n = 0;
  uint64_t count = 0;
  Buffer e;       // n + 1 uint32_t
  Buffer starts;  // count + 1 uint32_t
};

// Runs of equal keys[i] >> shift in n 64-bit keys (shift 64 or more: one run). Waits once, to read the count.
Segmentation segment_by_key(Device& dev, const Buffer& keys, uint64_t n, uint32_t shift = 0);

// The head flags of those runs: heads (n 32-bit values) = 1 where a run starts, else 0. Other flags may be set
// before the flags go to segment_by_heads (runs that must also break where something else changes).
void segment_heads(Device& dev, const Buffer& keys, Buffer& heads, uint64_t n, uint32_t shift = 0);

// The same from head flags (n 32-bit values, nonzero where a run starts; element 0 always starts one). Waits once.
Segmentation segment_by_heads(Device& dev, const Buffer& heads, uint64_t n);

// Stream compaction: positions (n + 1 uint32_t at least) receives, in order, the indices i < n where flags[i]
// (n 32-bit values, each 0 or 1) is 1, then n. Returns how many there are (waits once, to read the count).
uint64_t select_flagged(Device& dev, const Buffer& flags, Buffer& positions, uint64_t n);

// sums[s] = the exact 64-bit sum of run s's 32-bit values (sums holds count uint64_t values). With `planes`,
// values holds that many planes of n values (plane k at k * n), each summed over the same runs: sums[k * count + s].
void segmented_sum(Device& dev, const Segmentation& seg, const Buffer& values, Buffer& sums, uint32_t planes = 1);

// out[i] = the sum of the 32-bit values before element i in its run, exact in 64 bits (out holds n uint64_t).
void segmented_exclusive_scan(Device& dev, const Segmentation& seg, const Buffer& values, Buffer& out);

// out[s] = the position of run s's smallest 64-bit value, the first of equal ones (out holds count uint32_t).
void segmented_argmin(Device& dev, const Segmentation& seg, const Buffer& values, Buffer& out);

}  // namespace mv
