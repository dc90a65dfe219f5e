/* The exclusive scan's block sums with a work-group per block (scan.h's parameters and layout): the group's items
 * read consecutive values, one each in turn, where scan_reduce gives each work-item a block of its own to walk. On
 * devices that run a group's items side by side (a GPU's lanes, lavapipe's SIMD) those reads are contiguous across
 * the items: on lavapipe 3x faster than scan_reduce (a 12M-value scan's sums: 41 -> 14 ms). The apply keeps
 * scan.h's walk: a group's scan in shared memory, a round of values at a time, costs more in barriers than it
 * saves there (docs/decisions/radix-sort.md). A .comp declares MV_SHARED(mv_u64, scan_part, MV_SCAN_GROUP) before
 * including this header.
 *   scan_reduce_group: group b sums block b into sums[b].
 * Integer sums: the same bits as scan_reduce's in any order. Groups of at most MV_SCAN_GROUP items. */
#ifndef MV_SCAN_GROUP_H
#define MV_SCAN_GROUP_H
#include "scan.h"

MV_INLINE void mv_scan_reduce_group(MV_SHARED_PARAM(mv_u64, scan_part) MvBufU32 src, MvBufU64 sums, MvScanParams p,
                                    mv_u32 b, mv_u32 lid, mv_u32 items) {
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  mv_u64 acc = MV_U64(0u);
  for (mv_u32 i = begin + lid; i < end; i += items) acc += MV_U64(MV_LD(src, i));
  scan_part[lid] = acc;
  MV_BARRIER();
  if (lid == 0u) {
    mv_u64 total = MV_U64(0u);
    for (mv_u32 k = 0u; k < items; ++k) total += scan_part[k];
    MV_ST(sums, b, total);
  }
}

#endif
