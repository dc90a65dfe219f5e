/* Voxel colours from points: per-voxel means over Morton-sorted codes, every node's mean above them, and their
 * place in the depth-first (pre-order) attribute array. Host side: host/core/voxel/cloud_colours.cpp; the sums
 * and offsets themselves are the shared segmented_sum and exclusive_scan64, these kernels only do what those do
 * not: unpack, divide, and find each node's voxels.
 *
 * Where the codes leave room (3 x levels + 24 bits), a point's colour rides in its sort key, below the code
 * (colour_pack_keys; radix_sort_packed sorts the code alone), so the sort moves no colour column; the colour is
 * then the low word's 24 bits (`stride` 2 over the keys as 32-bit words). A point's planes, plane-major (plane k
 * of point i at k * n + i): its red, green and blue and a count of one. Their segmented sums over a voxel's
 * points give its mean.
 *
 * Every node from the voxels' sorted codes alone, with no pass per level: voxel i starts the nodes of every level
 * below the highest at which its code and voxel i - 1's differ, d[i] of them (levels + 1 for voxel 0, so the
 * root). In pre-order the nodes starting at earlier voxels come first, then those starting at voxel i from the
 * highest level down, so with o the exclusive scan of d, the node of level k starting at voxel i has index
 * o[i] + d[i] - 1 - k. Its voxels run from i to the first voxel whose code leaves it, at most 8^k further on (a
 * search), and its mean is the difference of the voxels' channel prefix sums there. d and the voxels' channels
 * are four planes of n values, scanned as one (plane k of voxel i at k * n + i): the scan's sums start at 0 for
 * d, so they are o, and a plane's differences do not see the planes before it. colour_nodes reads 32-bit sums
 * (the true sums mod 2^32): a node's channel sum is at most 255 x n, so below 2^32 / 255 voxels the differences
 * mod 2^32 are exact, and the scan writes half the bytes; colour_nodes_wide reads 64-bit sums. The width is the
 * entry's constant, not a parameter: a choice at each load slowed lavapipe by half.
 *   colour_pack_keys:   keys[i] = keys[i] << 24 | the point's 0xBBGGRR;
 *   colour_unpack:      points' packed 0xBBGGRR -> their MV_COLOUR_PLANES planes (r, g, b, 1);
 *   colour_level:       the 64-bit sums of n voxels' points (r, g, b, count) -> the voxels' planes: d, and each
 *                       channel sum / count rounded half up;
 *   colour_parent_keys: keys_up[s] = keys[starts[s]] >> shift, the voxels' codes from their points' runs;
 *   colour_starts:      the voxels' planes from their colours (a mesh's, or one point a voxel): d, r, g, b;
 *   colour_nodes(_wide): from the planes' exclusive scan (sums), a work-item per voxel: its own colour, then a
 *                       bounded loop over the (at most levels) nodes above it starting there: each node's voxel
 *                       range, mean, and its place in the attributes.
 * Integer arithmetic decides every value (a mean's float quotient is only an estimate that integers correct): the
 * same bits on every device. */
#ifndef MV_COLOUR_H
#define MV_COLOUR_H
#include "mv_lang.h"

#define MV_COLOUR_PLANES 4u
#define MV_COLOUR_COUNT 3u /* plane of the count */
#define MV_COLOUR_PAYLOAD 24u /* a point's colour packed below its code: key = code << 24 | 0xBBGGRR */

MV_STRUCT_BEGIN(MvColourParams)
  mv_u32 n;      /* elements of the dispatch */
  mv_u32 levels; /* colour_starts, colour_level: the root's level, the voxels' being 0 */
  mv_u32 shift;  /* colour_parent_keys: bits the keys shift right */
  mv_u32 stride; /* colour_unpack, colour_starts: words from one colour to the next (2: in packed keys' low words) */
MV_STRUCT_END(MvColourParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvColourParams, 16);
MV_LAYOUT_AT(MvColourParams, n, 0); MV_LAYOUT_AT(MvColourParams, levels, 4); MV_LAYOUT_AT(MvColourParams, shift, 8);
MV_LAYOUT_AT(MvColourParams, stride, 12);
#endif

MV_INLINE void mv_colour_pack_keys(MvBufU64 keys, MvBufU32 rgb, MvColourParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride)
    MV_ST(keys, i, (MV_LD(keys, i) << MV_COLOUR_PAYLOAD) | MV_U64(MV_LD(rgb, i) & 0xffffffu));
}

MV_INLINE void mv_colour_unpack(MvBufU32 rgb, MvBufU32 planes, MvColourParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 c = MV_LD(rgb, i * p.stride);
    for (mv_u32 k = 0u; k < 3u; ++k) MV_ST(planes, k * p.n + i, (c >> (8u * k)) & 255u);
    MV_ST(planes, MV_COLOUR_COUNT * p.n + i, 1u);
  }
}

/* sum / count rounded half up, for a mean of 8-bit values (at most 255): a float quotient within one of the answer,
 * then made exact in integers. An integer division is several times dearer on CPUs, scalar on lavapipe and
 * emulated on GPUs; the correction makes the bits independent of the device's float division. */
MV_INLINE mv_u32 mv_colour_mean(mv_u64 sum, mv_u64 count) {
  mv_u32 q = MV_U32(MV_F32(sum) / MV_F32(count) + 0.5f);
  mv_u64 twice = sum + sum + count, step = count + count; /* the answer q: q * step <= twice < (q + 1) * step */
  if (MV_U64(q) * step > twice) q -= 1u;
  else if (MV_U64(q + 1u) * step <= twice) q += 1u;
  return q;
}


MV_INLINE void mv_colour_parent_keys(MvBufU64 keys, MvBufU32 starts, MvBufU64 up, MvColourParams p, mv_u32 gid,
                                     mv_u32 stride) {
  for (mv_u32 s = gid; s < p.n; s += stride) MV_ST(up, s, MV_LD(keys, MV_LD(starts, s)) >> p.shift);
}

/* How many nodes start at voxel i of n sorted distinct codes (above). */
MV_INLINE mv_u32 mv_colour_node_starts(MvBufU64 keys, mv_u32 i, mv_u32 levels) {
  if (i == 0u) return levels + 1u;
  mv_u64 x = MV_LD(keys, i) ^ MV_LD(keys, i - 1u); /* nonzero: the codes are distinct */
  mv_u32 hi = MV_U32(x >> 32);
  return (hi != 0u ? 32u + MV_FIND_MSB(hi) : MV_FIND_MSB(MV_U32(x))) / 3u + 1u;
}

MV_INLINE void mv_colour_starts(MvBufU64 keys, MvBufU32 rgb, MvBufU32 planes, MvColourParams p, mv_u32 gid,
                                mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 c = MV_LD(rgb, i * p.stride);
    MV_ST(planes, i, mv_colour_node_starts(keys, i, p.levels));
    for (mv_u32 k = 0u; k < 3u; ++k) MV_ST(planes, (k + 1u) * p.n + i, (c >> (8u * k)) & 255u);
  }
}

MV_INLINE void mv_colour_level(MvBufU64 keys, MvBufU64 sums, MvBufU32 planes, MvColourParams p, mv_u32 gid,
                               mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u64 count = MV_LD(sums, MV_COLOUR_COUNT * p.n + i);
    MV_ST(planes, i, mv_colour_node_starts(keys, i, p.levels));
    for (mv_u32 c = 0u; c < 3u; ++c) MV_ST(planes, (c + 1u) * p.n + i, mv_colour_mean(MV_LD(sums, c * p.n + i), count));
  }
}

/* Prefix sum `at` of the planes' scan: 32-bit words, or 64-bit with `wide` (a constant of the entry). */
MV_INLINE mv_u64 mv_colour_prefix(MvBufU32 sums, mv_u32 wide, mv_u32 at) {
  if (wide == 0u) return MV_U64(MV_LD(sums, at));
  return MV_U64(MV_LD(sums, 2u * at)) | (MV_U64(MV_LD(sums, 2u * at + 1u)) << 32);
}

/* The sum of plane k over voxels [i, end): a difference of prefix sums, mod 2^32 where they are 32-bit. */
MV_INLINE mv_u64 mv_colour_range_sum(MvBufU32 sums, mv_u32 wide, mv_u32 n, mv_u32 k, mv_u32 i, mv_u32 end) {
  mv_u64 d = mv_colour_prefix(sums, wide, k * n + end) - mv_colour_prefix(sums, wide, k * n + i);
  return wide != 0u ? d : d & MV_U64(0xffffffffu);
}

MV_INLINE void mv_colour_nodes(MvBufU64 keys, MvBufU32 planes, MvBufU32 sums, MvBufU32 attributes, MvColourParams p,
                               mv_u32 wide, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 d = MV_LD(planes, i), last = MV_U32(mv_colour_prefix(sums, wide, i)) + d - 1u; /* the voxel's own index */
    mv_u32 packed = MV_LD(planes, p.n + i) | (MV_LD(planes, 2u * p.n + i) << 8u) | (MV_LD(planes, 3u * p.n + i) << 16u);
    MV_ST(attributes, last, packed);
    mv_u64 key = MV_LD(keys, i);
    mv_u32 end = i + 1u, below = end;
    for (mv_u32 k = 1u; k < d; ++k) { /* the nodes above the voxel that start with it */
      /* Voxels [i, end) are in the level below's node, so in this one. It goes on past them where a sibling of
       * that node starts at `end` (d[end] <= k); it holds at most 8^k voxels. The end is then found by galloping
       * from there and a binary search: on sparse or noisy clouds it is mostly near. */
      if (end < p.n && MV_LD(planes, end) <= k) {
        mv_u32 shift = 3u * k, bound = p.n, lo = end + 1u, hi = end + 1u, step = 1u;
        mv_u64 node = key >> shift;
        if (shift < 31u && p.n - i > (1u << shift)) bound = i + (1u << shift);
        while (hi < bound && (MV_LD(keys, hi) >> shift) == node) { /* [lo, hi] inside: look twice as far */
          lo = hi + 1u;
          hi = bound - hi > step ? hi + step : bound;
          step *= 2u;
        }
        while (lo < hi) { /* the first voxel past the node is in [lo, hi] */
          mv_u32 mid = lo + (hi - lo) / 2u;
          if ((MV_LD(keys, mid) >> shift) == node) lo = mid + 1u;
          else hi = mid;
        }
        end = lo;
      }
      if (end != below) { /* else the same voxels as the node below: its colour */
        mv_u64 count = MV_U64(end - i), r = mv_colour_range_sum(sums, wide, p.n, 1u, i, end),
               g = mv_colour_range_sum(sums, wide, p.n, 2u, i, end),
               b = mv_colour_range_sum(sums, wide, p.n, 3u, i, end);
        packed = mv_colour_mean(r, count) | (mv_colour_mean(g, count) << 8u) | (mv_colour_mean(b, count) << 16u);
      }
      below = end;
      MV_ST(attributes, last - k, packed);
    }
  }
}

#endif
