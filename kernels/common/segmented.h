/* Segmented operations over n elements cut into runs (segments), the shared pieces under per-node work on sorted
 * codes (a point hierarchy's cells and parents, a voxel's fragments). Host side: host/core/primitives/segmented.cpp.
 * A segmentation is E, the exclusive scan of head flags (E[i] = segments starting before i, E[n] = their count):
 * element i starts a segment when E[i + 1] > E[i] and belongs to segment E[i + 1] - 1.
 *   seg_heads:       heads[i] = 1 where (keys[i] >> shift) differs from the key before (always at i = 0);
 *   seg_starts:      starts[s] = the first element of segment s, starts[count] = n;
 *   seg_sum:         sums[s] = P[starts[s + 1]] - P[starts[s]] from P, an exclusive 64-bit scan of the values;
 *   seg_scan:        dst[i] = P[i] - P[first element of i's segment], the exclusive scan within each segment;
 *   seg_argmin_*:    the position of each segment's smallest 64-bit value (the first of equals), reduce-then-scan
 *                    over blocks as scan.h does: a block's last segment is carried into the next blocks, so a
 *                    segment of millions is spread over as many work-items as any other run of elements.
 * Every result is exact integer arithmetic: the same bits on every device. */
#ifndef MV_SEGMENTED_H
#define MV_SEGMENTED_H
#include "mv_lang.h"

MV_STRUCT_BEGIN(MvSegParams)
  mv_u32 n;          /* elements */
  mv_u32 count;      /* segments (seg_sum) */
  mv_u32 blocks;     /* seg_argmin_*: blocks of elements, one work-item each */
  mv_u32 block_size; /* seg_argmin_*: elements per block (the last may be short) */
  mv_u32 shift;      /* seg_heads: keys compare shifted right by this (64 or more: one segment) */
  mv_u32 planes;     /* seg_sum: planes of n values each, summed over the same segments (0 counts as 1) */
MV_STRUCT_END(MvSegParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvSegParams, 24);
MV_LAYOUT_AT(MvSegParams, n, 0); MV_LAYOUT_AT(MvSegParams, count, 4); MV_LAYOUT_AT(MvSegParams, blocks, 8);
MV_LAYOUT_AT(MvSegParams, block_size, 12); MV_LAYOUT_AT(MvSegParams, shift, 16); MV_LAYOUT_AT(MvSegParams, planes, 20);
#endif

/* Bit 63 of a carried index word: the block holds a segment head (reduce) / the carry is valid (small). */
#define MV_SEG_FLAG (MV_U64(1u) << 63)

/* seg_heads and seg_starts: block_size nonzero gives each work-item that many consecutive elements (CPU devices,
 * which run a work-item's loop alone), else grid-stride. */
MV_INLINE void mv_seg_heads(MvBufU64 keys, MvBufU32 heads, MvSegParams p, mv_u32 gid, mv_u32 stride) {
  MvItems r = mv_items(p.block_size, gid, stride, p.n);
  for (mv_u32 i = r.begin; i < r.end; i += r.step) {
    bool head = i == 0u;
    if (!head && p.shift < 64u) head = (MV_LD(keys, i) >> p.shift) != (MV_LD(keys, i - 1u) >> p.shift);
    MV_ST(heads, i, head ? 1u : 0u);
  }
}

MV_INLINE void mv_seg_starts(MvBufU32 e, MvBufU32 starts, MvSegParams p, mv_u32 gid, mv_u32 stride) {
  MvItems r = mv_items(p.block_size, gid, stride, p.n);
  for (mv_u32 i = r.begin; i < r.end; i += r.step) {
    mv_u32 s = MV_LD(e, i);
    if (MV_LD(e, i + 1u) > s) MV_ST(starts, s, i);
  }
  if (gid == 0u) MV_ST(starts, MV_LD(e, p.n), p.n);
}

/* sums[k * count + s] = the sum of segment s of plane k: `prefix` is the exclusive scan of every plane in turn
 * (plane k's values at k * n), so a segment's sum is the difference of two prefixes within its plane. */
MV_INLINE void mv_seg_sum(MvBufU64 prefix, MvBufU32 starts, MvBufU64 sums, MvSegParams p, mv_u32 gid, mv_u32 stride) {
  mv_u32 planes = MV_MAX(p.planes, 1u);
  for (mv_u32 s = gid; s < p.count; s += stride) { /* a work-item per segment, its planes in turn */
    mv_u32 first = MV_LD(starts, s), end = MV_LD(starts, s + 1u);
    for (mv_u32 k = 0u; k < planes; ++k)
      MV_ST(sums, k * p.count + s, MV_LD(prefix, k * p.n + end) - MV_LD(prefix, k * p.n + first));
  }
}

MV_INLINE void mv_seg_scan(MvBufU64 prefix, MvBufU32 e, MvBufU32 starts, MvBufU64 dst, MvSegParams p, mv_u32 gid,
                           mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride)
    MV_ST(dst, i, MV_LD(prefix, i) - MV_LD(prefix, MV_LD(starts, MV_LD(e, i + 1u) - 1u)));
}

/* agg[2b], agg[2b + 1] = block b's last segment so far: its smallest value and that value's position, with
 * MV_SEG_FLAG set when the segment starts inside the block (else it goes on from the blocks before). */
MV_INLINE void mv_seg_argmin_reduce(MvBufU64 values, MvBufU32 e, MvBufU64 agg, MvSegParams p, mv_u32 b) {
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  mv_u64 best = MV_LD(values, begin);
  mv_u32 at = begin;
  mv_u32 s0 = MV_LD(e, begin + 1u); /* e[i] as the loop reaches i + 1: each value of e is read once */
  bool head = s0 > MV_LD(e, begin);
  for (mv_u32 i = begin + 1u; i < end; ++i) {
    mv_u64 v = MV_LD(values, i);
    mv_u32 s1 = MV_LD(e, i + 1u);
    if (s1 > s0) {
      head = true;
      best = v;
      at = i;
    } else if (v < best) {
      best = v;
      at = i;
    }
    s0 = s1;
  }
  MV_ST(agg, 2u * b, best);
  MV_ST(agg, 2u * b + 1u, MV_U64(at) | (head ? MV_SEG_FLAG : MV_U64(0u)));
}

/* In place: agg[2b], agg[2b + 1] become what flows into block b from the blocks before it (MV_SEG_FLAG: valid).
 * Earlier positions win ties, so a carry is replaced only by a strictly smaller value. */
MV_INLINE void mv_seg_argmin_small(MvBufU64 agg, MvSegParams p) {
  mv_u64 best = MV_U64(0u);
  mv_u64 at = MV_U64(0u);
  for (mv_u32 b = 0u; b < p.blocks; ++b) {
    mv_u64 v = MV_LD(agg, 2u * b);
    mv_u64 w = MV_LD(agg, 2u * b + 1u);
    MV_ST(agg, 2u * b, best);
    MV_ST(agg, 2u * b + 1u, at);
    if ((w & MV_SEG_FLAG) != MV_U64(0u) || (at & MV_SEG_FLAG) == MV_U64(0u) || v < best) {
      best = v;
      at = (w & ~MV_SEG_FLAG) | MV_SEG_FLAG;
    }
  }
}

/* dst[s] = the position of segment s's smallest value, written by the block where s ends. */
MV_INLINE void mv_seg_argmin_apply(MvBufU64 values, MvBufU32 e, MvBufU64 agg, MvBufU32 dst, MvSegParams p, mv_u32 b) {
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  mv_u64 best = MV_LD(agg, 2u * b);
  mv_u64 carry = MV_LD(agg, 2u * b + 1u);
  bool valid = (carry & MV_SEG_FLAG) != MV_U64(0u);
  mv_u32 at = MV_U32(carry & MV_U64(0xffffffffu));
  mv_u32 s0 = MV_LD(e, begin);
  mv_u32 s1 = MV_LD(e, begin + 1u);
  for (mv_u32 i = begin; i < end; ++i) {
    mv_u64 v = MV_LD(values, i);
    if (!valid || s1 > s0 || v < best) {
      best = v;
      at = i;
      valid = true;
    }
    /* past the last element the run ends: e[n] + 1 stands for the e[n + 1] there is not */
    mv_u32 s2 = i + 1u < p.n ? MV_LD(e, i + 2u) : s1 + 1u;
    if (s2 > s1) MV_ST(dst, s1 - 1u, at);
    s0 = s1;
    s1 = s2;
  }
}

#endif /* MV_SEGMENTED_H */
