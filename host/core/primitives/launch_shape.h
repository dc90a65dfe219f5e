// How many work-items to give block-per-work-item kernels, and with what work-group size, per device.
#pragma once
#include <algorithm>
#include <cstdint>
#include <thread>

#include "megavox/device.h"

namespace mv {

struct BlockShape {
  uint32_t blocks;      // number of contiguous blocks (one work-item each)
  uint32_t block_size;  // items per block (the last block may be short)
  uint32_t local_size;  // work-group size of the dispatch
  uint32_t groups;      // work-groups to dispatch (covers `blocks`)
};

// CPU devices: a few blocks per hardware thread; GPUs: thousands of blocks. Work-groups of the device's
// preferred size (PoCL 1: it runs each work-item as a plain loop; lavapipe 8, its SIMD width; GPUs 64).
// Blocks stay below DeviceInfo::max_loop_iterations / 2 items where the driver caps loops (llvmpipe).
inline BlockShape block_shape(const DeviceInfo& info, uint64_t n, uint32_t min_block = 4096) {
  bool gpu = info.massively_parallel;
  uint32_t threads = std::max<uint32_t>({info.compute_units, std::thread::hardware_concurrency(), 1u});
  uint64_t max_blocks = gpu ? 8192 : uint64_t{threads} * 8;
  uint64_t blocks = std::clamp<uint64_t>((n + min_block - 1) / min_block, 1, max_blocks);
  uint64_t block_size = std::max<uint64_t>(1, (n + blocks - 1) / blocks);
  if (info.max_loop_iterations)  // keep every per-block loop well inside the driver's iteration cap
    block_size = std::min<uint64_t>(block_size, (info.max_loop_iterations + 1) / 2);
  blocks = std::max<uint64_t>(1, (n + block_size - 1) / block_size);
  uint32_t local = info.preferred_work_group_size;
  BlockShape s;
  s.blocks = static_cast<uint32_t>(blocks);
  s.block_size = static_cast<uint32_t>(block_size);
  s.local_size = local;
  s.groups = static_cast<uint32_t>((blocks + local - 1) / local);
  return s;
}

}  // namespace mv
