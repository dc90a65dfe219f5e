#include "common/gather.h"

#include <algorithm>
#include <string>

#include "megavox/error.h"
#include "megavox/primitives.h"
#include "primitives/chunking.h"

namespace mv {

void gather_records(Device& dev, const Buffer& src, const Buffer& index, Buffer& dst, uint64_t n,
                    uint32_t record_bytes, const GatherSlice& slice) {
  if (record_bytes == 0) throw Error("gather: records of 0 bytes");
  const uint32_t unit_shift = record_bytes % 4 == 0 ? 2 : record_bytes % 2 == 0 ? 1 : 0;
  const uint64_t units = n * (record_bytes >> unit_shift);
  const uint64_t words = (n * record_bytes + 3) / 4;
  detail::check_device_items("gather", units);  // every unit index, and so every word index, stays 32-bit
  if (words == 0) return;
  MvGatherParams p{};
  p.words = static_cast<uint32_t>(words);
  p.units = static_cast<uint32_t>(units);
  p.per_record = record_bytes >> unit_shift;
  p.unit_shift = unit_shift;
  p.lo = slice.first;
  p.count = slice.count;
  p.merge = slice.merge ? 1 : 0;
  // A work-item per record of whole words, per word of 2-byte units, per 4 records (per_record words) of bytes.
  const uint64_t items = unit_shift == 2 ? n : unit_shift == 1 ? words : (words + p.per_record - 1) / p.per_record;
  const DeviceInfo& info = dev.info();
  uint32_t local = 64;
  uint64_t work_items = items;
  if (!info.massively_parallel && info.preferred_work_group_size <= 1 && unit_shift != 0) {
    // Work-items that are CPU threads running their items as a loop: blocks of records (words), several a thread
    // for balance, each read with prefetches (the loop has no way to overlap its random reads otherwise).
    local = 1;
    const uint64_t blocks = uint64_t{std::max<uint32_t>(info.compute_units, 1)} * 16;
    uint64_t block = std::max<uint64_t>((items + blocks - 1) / blocks, 1024);
    if (info.max_loop_iterations) block = std::min<uint64_t>(block, info.max_loop_iterations);
    p.block = static_cast<uint32_t>(block);
    work_items = (items + block - 1) / block;
  }
  dev.dispatch(dev.kernel(KernelId::gather_records), dev.groups_for(work_items, local), local, {&src, &index, &dst}, p);
  dev.barrier();
}

}  // namespace mv
