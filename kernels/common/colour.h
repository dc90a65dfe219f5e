/* Voxel colours from points: per-voxel and per-node means over Morton-sorted codes, and their place in the
 * depth-first (pre-order) attribute array. Host side: host/core/voxel/cloud_colours.cpp; the sums themselves are
 * the shared segmented_sum (kernels/common/segmented.h), these kernels only do what it does not: unpack, divide,
 * carry the sums up a level, and scatter into depth-first order.
 *
 * Planes: a level of n elements carries MV_COLOUR_PLANES 32-bit planes, plane-major (plane k of element i at
 * k * n + i): the low 32-bit words of the red, green and blue sums, the voxel count below, the subtree size
 * (octree nodes in the element's subtree, itself included), then the sums' high words (a sum over more than
 * 2^32 / 255 voxels passes 32 bits). The segmented sums of each plane over the elements' parents give that many
 * 64-bit planes for the level above; the host sums only the leading planes that can be nonzero.
 * Voxels carry no planes: a voxel counts as one sample of its colour, with subtree size 1, so its planes are
 * (r, g, b, 1, 1, 0, 0, 0) from its packed colour alone, and the kernels that read a level below take its packed
 * colours instead where that level is the voxels (`leaf` 1).
 *   colour_unpack:      points' packed 0xBBGGRR -> their first MV_COLOUR_COUNT + 1 planes (r, g, b, 1): a point
 *                       is one sample;
 *   colour_level:       the 64-bit sums of n voxels' points (r, g, b, count) -> rgb[i], each channel sum / count
 *                       rounded half up;
 *   colour_parent_keys: keys_up[s] = keys[starts[s]] >> shift, the codes of the level above (the voxels' from
 *                       their points' runs, shift 0);
 *   colour_parents:     a level above the voxels in one pass, a work-item per node: its code, the sums of the
 *                       first `used` planes over its children (at most 8, consecutive from starts[s]; `leaf`: the
 *                       voxels, whose planes come from their colours), its colour, its planes and its subtree
 *                       size; bounded loops (the segmented_sum of the points' runs into voxels has no bound);
 *   colour_place:       index[i] = parent_index[parent of i] + 1 + the subtree sizes of its earlier siblings (at
 *                       most 7; `leaf`: voxels, size 1 each), attributes[index[i]] = rgb[i].
 * Integer arithmetic only: the same bits on every device. */
#ifndef MV_COLOUR_H
#define MV_COLOUR_H
#include "mv_lang.h"

#define MV_COLOUR_PLANES 8u
#define MV_COLOUR_COUNT 3u /* plane of the voxel count */
#define MV_COLOUR_SIZE 4u  /* plane of the subtree size */
#define MV_COLOUR_HIGH 5u  /* first plane of the sums' high words */

MV_STRUCT_BEGIN(MvColourParams)
  mv_u32 n;     /* elements of the dispatch */
  mv_u32 leaf;  /* colour_parents, colour_place: 1 where the level below is the voxels */
  mv_u32 shift; /* colour_parent_keys, colour_parents: bits the keys shift right */
  mv_u32 below; /* colour_parents: elements of the level below (its planes' stride) */
  mv_u32 used;  /* colour_parents: the leading planes of the level below summed (the rest can only be zero) */
  mv_u32 pad0;
MV_STRUCT_END(MvColourParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvColourParams, 24);
MV_LAYOUT_AT(MvColourParams, n, 0); MV_LAYOUT_AT(MvColourParams, leaf, 4); MV_LAYOUT_AT(MvColourParams, shift, 8);
MV_LAYOUT_AT(MvColourParams, below, 12); MV_LAYOUT_AT(MvColourParams, used, 16); MV_LAYOUT_AT(MvColourParams, pad0, 20);
#endif

MV_INLINE void mv_colour_unpack(MvBufU32 rgb, MvBufU32 planes, MvColourParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 c = MV_LD(rgb, i);
    for (mv_u32 k = 0u; k < 3u; ++k) MV_ST(planes, k * p.n + i, (c >> (8u * k)) & 255u);
    MV_ST(planes, MV_COLOUR_COUNT * p.n + i, 1u);
  }
}

/* sum / count rounded half up, without forming 2 * sum; in 32 bits where both fit (most nodes: a 64-bit division
 * is several times dearer on CPUs and emulated on GPUs). */
MV_INLINE mv_u32 mv_colour_mean(mv_u64 sum, mv_u64 count) {
  if (((sum | count) >> 32) == MV_U64(0u)) {
    mv_u32 s32 = MV_U32(sum), c32 = MV_U32(count);
    mv_u32 q32 = s32 / c32;
    mv_u32 r32 = s32 - q32 * c32;
    return q32 + (r32 >= c32 - r32 ? 1u : 0u);
  }
  mv_u64 q = sum / count;
  mv_u64 r = sum - q * count;
  return MV_U32(q) + (r >= count - r ? 1u : 0u);
}

MV_INLINE void mv_colour_level(MvBufU64 sums, MvBufU32 rgb, MvColourParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u64 count = MV_LD(sums, MV_COLOUR_COUNT * p.n + i);
    mv_u32 packed = 0u;
    for (mv_u32 c = 0u; c < 3u; ++c) packed |= mv_colour_mean(MV_LD(sums, c * p.n + i), count) << (8u * c);
    MV_ST(rgb, i, packed);
  }
}

MV_INLINE void mv_colour_parent_keys(MvBufU64 keys, MvBufU32 starts, MvBufU64 up, MvColourParams p, mv_u32 gid,
                                     mv_u32 stride) {
  for (mv_u32 s = gid; s < p.n; s += stride) MV_ST(up, s, MV_LD(keys, MV_LD(starts, s)) >> p.shift);
}

MV_INLINE void mv_colour_parents(MvBufU64 keys, MvBufU32 below_planes, MvBufU32 starts, MvBufU64 up, MvBufU32 rgb,
                                 MvBufU32 planes, MvBufU32 sizes, MvColourParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 s = gid; s < p.n; s += stride) { /* a node's planes in turn: its children's range read once each */
    mv_u32 first = MV_LD(starts, s), end = MV_LD(starts, s + 1u), packed = 0u;
    MV_ST(up, s, MV_LD(keys, first) >> p.shift);
    mv_u64 sum[MV_COLOUR_PLANES];
    for (mv_u32 k = 0u; k < MV_COLOUR_PLANES; ++k) {
      sum[k] = MV_U64(0u);
      if (k >= p.used) continue; /* the planes past `used` can only sum to zero */
      if (p.leaf == 0u)
        for (mv_u32 c = first; c < end; ++c) sum[k] += MV_U64(MV_LD(below_planes, k * p.below + c));
      else if (k < 3u) /* voxels: `below_planes` holds their packed colours */
        for (mv_u32 c = first; c < end; ++c) sum[k] += MV_U64((MV_LD(below_planes, c) >> (8u * k)) & 255u);
      else if (k == MV_COLOUR_COUNT || k == MV_COLOUR_SIZE)
        sum[k] = MV_U64(end - first);
    }
    for (mv_u32 c = 0u; c < 3u; ++c) {
      mv_u64 total = sum[c] + (sum[MV_COLOUR_HIGH + c] << 32);
      packed |= mv_colour_mean(total, sum[MV_COLOUR_COUNT]) << (8u * c);
      MV_ST(planes, c * p.n + s, MV_U32(total));
      MV_ST(planes, (MV_COLOUR_HIGH + c) * p.n + s, MV_U32(total >> 32));
    }
    MV_ST(rgb, s, packed);
    MV_ST(planes, MV_COLOUR_COUNT * p.n + s, MV_U32(sum[MV_COLOUR_COUNT]));
    MV_ST(planes, MV_COLOUR_SIZE * p.n + s, 1u + MV_U32(sum[MV_COLOUR_SIZE]));
    MV_ST(sizes, s, 1u + MV_U32(sum[MV_COLOUR_SIZE]));
  }
}

MV_INLINE void mv_colour_place(MvBufU32 e, MvBufU32 starts, MvBufU32 sizes, MvBufU32 parent_index, MvBufU32 rgb,
                               MvBufU32 index, MvBufU32 attributes, MvColourParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u32 parent = MV_LD(e, i + 1u) - 1u;
    mv_u32 at = MV_LD(parent_index, parent) + 1u;
    if (p.leaf != 0u) at += i - MV_LD(starts, parent); /* voxels: size 1 each */
    else
      for (mv_u32 c = MV_LD(starts, parent); c < i; ++c) at += MV_LD(sizes, c); /* at most 7 earlier siblings */
    MV_ST(index, i, at);
    MV_ST(attributes, at, MV_LD(rgb, i));
  }
}

#endif
