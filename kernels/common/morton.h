/* Morton (Z-order) codes: bit i of x, y, z goes to bits 3i, 3i+1, 3i+2 (x lowest).
 * 64-bit keys interleave 3 x 21 bits (grids up to 2M per axis), 32-bit keys 3 x 10 bits (1024 per axis).
 * Coordinate bits above those are ignored. */
#ifndef MV_MORTON_H
#define MV_MORTON_H
#include "mv_lang.h"

MV_STRUCT_BEGIN(MvMortonParams)
  mv_u32 n; /* number of points (x, y, z triples of 32-bit grid coordinates) */
  mv_u32 pad0;
MV_STRUCT_END(MvMortonParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvMortonParams, 8);
MV_LAYOUT_AT(MvMortonParams, n, 0); MV_LAYOUT_AT(MvMortonParams, pad0, 4);
#endif

MV_INLINE mv_u64 mv_morton_spread21(mv_u64 v) {
  v &= 0x1fffffUL;
  v = (v | (v << 32)) & 0x1f00000000ffffUL;
  v = (v | (v << 16)) & 0x1f0000ff0000ffUL;
  v = (v | (v << 8)) & 0x100f00f00f00f00fUL;
  v = (v | (v << 4)) & 0x10c30c30c30c30c3UL;
  v = (v | (v << 2)) & 0x1249249249249249UL;
  return v;
}

MV_INLINE mv_u32 mv_morton_spread10(mv_u32 v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

MV_INLINE mv_u64 mv_morton3_64(mv_u32 x, mv_u32 y, mv_u32 z) {
  return mv_morton_spread21(MV_U64(x)) | (mv_morton_spread21(MV_U64(y)) << 1) | (mv_morton_spread21(MV_U64(z)) << 2);
}

/* The inverse of mv_morton_spread21: every third bit of v, packed. */
MV_INLINE mv_u32 mv_morton_compact21(mv_u64 v) {
  v &= 0x1249249249249249UL;
  v = (v ^ (v >> 2)) & 0x10c30c30c30c30c3UL;
  v = (v ^ (v >> 4)) & 0x100f00f00f00f00fUL;
  v = (v ^ (v >> 8)) & 0x1f0000ff0000ffUL;
  v = (v ^ (v >> 16)) & 0x1f00000000ffffUL;
  v = (v ^ (v >> 32)) & 0x1fffffUL;
  return MV_U32(v);
}

/* Coordinate `axis` (0 = x, 1 = y, 2 = z) of a 64-bit Morton key. */
MV_INLINE mv_u32 mv_morton3_64_axis(mv_u64 key, mv_u32 axis) { return mv_morton_compact21(key >> axis); }

MV_INLINE mv_u32 mv_morton3_32(mv_u32 x, mv_u32 y, mv_u32 z) {
  return mv_morton_spread10(x) | (mv_morton_spread10(y) << 1) | (mv_morton_spread10(z) << 2);
}

/* Grid-stride over points: xyz holds 3n coordinates, so their index is 64-bit (3i passes 2^31 at 716 M points). */
MV_INLINE void mv_morton_encode64(MvBufU32 xyz, MvBufU64 keys, MvMortonParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u64 j = MV_U64(3u) * MV_U64(i);
    MV_ST(keys, i, mv_morton3_64(MV_LD_FAR(xyz, j), MV_LD_FAR(xyz, j + MV_U64(1u)), MV_LD_FAR(xyz, j + MV_U64(2u))));
  }
}

MV_INLINE void mv_morton_encode32(MvBufU32 xyz, MvBufU32 keys, MvMortonParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u64 j = MV_U64(3u) * MV_U64(i);
    MV_ST(keys, i, mv_morton3_32(MV_LD_FAR(xyz, j), MV_LD_FAR(xyz, j + MV_U64(1u)), MV_LD_FAR(xyz, j + MV_U64(2u))));
  }
}

#endif
