/* Exclusive prefix sum of 32-bit values, reduce-then-scan (no cross-work-group waiting):
 *   scan_reduce: work-item b sums block b of the input into sums[b]
 *   scan_small:  one work-item scans sums[0..blocks) in place (exclusive) and writes the total to sums[blocks]
 *   scan_apply:  work-item b scans block b again, starting from sums[b]
 * The shared piece under radix sort, stream compaction and unique. */
#ifndef MV_SCAN_H
#define MV_SCAN_H
#include "mv_lang.h"

MV_STRUCT_BEGIN(MvScanParams)
  mv_u32 n;          /* number of values */
  mv_u32 blocks;     /* number of blocks */
  mv_u32 block_size; /* values per block */
  mv_u32 pad0;
MV_STRUCT_END(MvScanParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvScanParams, 16);
MV_LAYOUT_AT(MvScanParams, n, 0); MV_LAYOUT_AT(MvScanParams, blocks, 4); MV_LAYOUT_AT(MvScanParams, block_size, 8);
MV_LAYOUT_AT(MvScanParams, pad0, 12);
#endif

MV_INLINE void mv_scan_reduce(MvBufU32 src, MvBufU32 sums, MvScanParams p, mv_u32 b) {
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  mv_u32 acc = 0u;
  for (mv_u32 i = begin; i < end; ++i) acc += MV_LD(src, i);
  MV_ST(sums, b, acc);
}

/* In place over data[0..n), total written to data[n]. */
MV_INLINE void mv_scan_small(MvBufU32 data, mv_u32 n) {
  mv_u32 acc = 0u;
  for (mv_u32 i = 0u; i < n; ++i) {
    mv_u32 v = MV_LD(data, i);
    MV_ST(data, i, acc);
    acc += v;
  }
  MV_ST(data, n, acc);
}

MV_INLINE void mv_scan_apply(MvBufU32 src, MvBufU32 dst, MvBufU32 sums, MvScanParams p, mv_u32 b) {
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  mv_u32 acc = MV_LD(sums, b);
  for (mv_u32 i = begin; i < end; ++i) {
    mv_u32 v = MV_LD(src, i);
    MV_ST(dst, i, acc);
    acc += v;
  }
}

#endif
