/* Exclusive prefix sum of 32-bit values, reduce-then-scan (no cross-work-group waiting):
 *   scan_reduce: work-item b sums block b of the input into sums[b]
 *   scan_small:  one work-item scans sums[0..blocks) in place (exclusive, from `start`) and writes the total
 *                to sums[blocks]
 *   scan_apply:  work-item b scans block b again, starting from sums[b]
 * Block sums are 64-bit, so with `wide` the output is exact 64-bit sums (a count past 2^32); without it the
 * output is 32-bit, i.e. the same sums mod 2^32. The shared piece under radix sort, stream compaction and
 * unique. One call covers at most MV_MAX_ITEMS values, so block ends and indices stay inside 32 bits. */
#ifndef MV_SCAN_H
#define MV_SCAN_H
#include "mv_lang.h"

#define MV_SCAN_GROUP 64 /* the most items a group of scan_reduce_group (scan_group.h) has */

MV_STRUCT_BEGIN(MvScanParams)
  mv_u32 n;          /* number of values */
  mv_u32 blocks;     /* number of blocks */
  mv_u32 block_size; /* values per block */
  mv_u32 wide;       /* nonzero: dst holds 64-bit sums */
  mv_u32 start_lo;   /* scan_small: the first sum, low and high word */
  mv_u32 start_hi;
MV_STRUCT_END(MvScanParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvScanParams, 24);
MV_LAYOUT_AT(MvScanParams, n, 0); MV_LAYOUT_AT(MvScanParams, blocks, 4); MV_LAYOUT_AT(MvScanParams, block_size, 8);
MV_LAYOUT_AT(MvScanParams, wide, 12); MV_LAYOUT_AT(MvScanParams, start_lo, 16); MV_LAYOUT_AT(MvScanParams, start_hi, 20);
#endif

MV_INLINE void mv_scan_reduce(MvBufU32 src, MvBufU64 sums, MvScanParams p, mv_u32 b) {
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  mv_u64 acc = MV_U64(0u);
  for (mv_u32 i = begin; i < end; ++i) acc += MV_U64(MV_LD(src, i));
  MV_ST(sums, b, acc);
}

/* In place over data[0..p.n), from p's start; the total written to data[p.n]. */
MV_INLINE void mv_scan_small(MvBufU64 data, MvScanParams p) {
  mv_u64 acc = MV_U64(p.start_lo) | (MV_U64(p.start_hi) << 32);
  for (mv_u32 i = 0u; i < p.n; ++i) {
    mv_u64 v = MV_LD(data, i);
    MV_ST(data, i, acc);
    acc += v;
  }
  MV_ST(data, p.n, acc);
}

MV_INLINE void mv_scan_apply(MvBufU32 src, MvBufU32 dst, MvBufU64 sums, MvScanParams p, mv_u32 b) {
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  if (p.wide != 0u) {
    mv_u64 acc = MV_LD(sums, b);
    for (mv_u32 i = begin; i < end; ++i) {
      mv_u32 v = MV_LD(src, i);
      MV_ST_U64(dst, i, acc);
      acc += MV_U64(v);
    }
  } else {
    mv_u32 acc = MV_U32(MV_LD(sums, b));
    for (mv_u32 i = begin; i < end; ++i) {
      mv_u32 v = MV_LD(src, i);
      MV_ST(dst, i, acc);
      acc += v;
    }
  }
}

#endif
