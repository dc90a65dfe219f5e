/* Point-cloud kernels (host side: host/core/points/point_kernels.cpp) and the parameters the point kernels share.
 *   point_bounds: each work-item's min and max per axis over its grid-stride share of the points, for the cube;
 *   point_codes: the 63-bit Morton code of each point's cell in the cloud's cube, and its index, for the sort.
 * The OMiCroN builder's representative kernels are in omicron.h. */
#ifndef MV_POINTS_H
#define MV_POINTS_H
#include "mv_lang.h"
#include "morton.h"

MV_STRUCT_BEGIN(MvPointParams)
  mv_u32 n;          /* points */
  mv_u32 shift;      /* point_codes: input-grid units per Morton cell are 2^shift */
  mv_u32 min_x;      /* point_codes: the cube's min corner, the bits of the int32 coordinates */
  mv_u32 min_y;
  mv_u32 min_z;
  mv_u32 base;       /* point_codes: the index of the first point of this dispatch */
  mv_u32 lshift;     /* point_codes: a cloud narrower than 2^21 units is scaled up: cells are d << lshift */
  mv_u32 first;      /* point_codes: where this dispatch's first code and index go in keys and index */
MV_STRUCT_END(MvPointParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvPointParams, 32);
MV_LAYOUT_AT(MvPointParams, n, 0); MV_LAYOUT_AT(MvPointParams, shift, 4); MV_LAYOUT_AT(MvPointParams, min_x, 8);
MV_LAYOUT_AT(MvPointParams, min_y, 12); MV_LAYOUT_AT(MvPointParams, min_z, 16); MV_LAYOUT_AT(MvPointParams, base, 20);
MV_LAYOUT_AT(MvPointParams, lshift, 24); MV_LAYOUT_AT(MvPointParams, first, 28);
#endif

/* Work-item gid's bounds go to partial[6 gid ...]: min x, y, z, then max x, y, z, each as its int32 bits with the
 * sign bit flipped (so that unsigned order is signed order); a work-item without points writes the empty box. */
MV_INLINE void mv_point_bounds(MvBufU32 xyz, MvBufU32 partial, MvPointParams p, mv_u32 gid, mv_u32 stride) {
  mv_u32 lo0 = 0xffffffffu, lo1 = 0xffffffffu, lo2 = 0xffffffffu, hi0 = 0u, hi1 = 0u, hi2 = 0u;
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u64 j = MV_U64(3u) * MV_U64(i);
    mv_u32 x = MV_LD_FAR(xyz, j) ^ 0x80000000u;
    mv_u32 y = MV_LD_FAR(xyz, j + MV_U64(1u)) ^ 0x80000000u;
    mv_u32 z = MV_LD_FAR(xyz, j + MV_U64(2u)) ^ 0x80000000u;
    lo0 = MV_MIN(lo0, x); lo1 = MV_MIN(lo1, y); lo2 = MV_MIN(lo2, z);
    hi0 = MV_MAX(hi0, x); hi1 = MV_MAX(hi1, y); hi2 = MV_MAX(hi2, z);
  }
  mv_u32 o = 6u * gid;
  MV_ST(partial, o, lo0); MV_ST(partial, o + 1u, lo1); MV_ST(partial, o + 2u, lo2);
  MV_ST(partial, o + 3u, hi0); MV_ST(partial, o + 4u, hi1); MV_ST(partial, o + 5u, hi2);
}

/* xyz: 3 int32 per point (as their bits). The difference to the min corner is taken modulo 2^32, which is exact
 * since it lies in [0, 2^32). */
MV_INLINE void mv_point_codes(MvBufU32 xyz, MvBufU64 keys, MvBufU32 index, MvPointParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) {
    mv_u64 j = MV_U64(3u) * MV_U64(i);
    mv_u32 x = ((MV_LD_FAR(xyz, j) - p.min_x) >> p.shift) << p.lshift;
    mv_u32 y = ((MV_LD_FAR(xyz, j + MV_U64(1u)) - p.min_y) >> p.shift) << p.lshift;
    mv_u32 z = ((MV_LD_FAR(xyz, j + MV_U64(2u)) - p.min_z) >> p.shift) << p.lshift;
    MV_ST(keys, p.first + i, mv_morton3_64(x, y, z));
    MV_ST(index, p.first + i, p.base + i);
  }
}

#endif
