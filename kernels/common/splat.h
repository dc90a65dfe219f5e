/* Depth-tested point splats in integer arithmetic, so every device draws the same pixels (host side:
 * host/core/points/point_render.cpp; reference: host/ref/splat_reference.cpp).
 *   splat_depth: each point's square of (2 radius + 1)^2 pixels takes the minimum of its depth key;
 *   splat_index: where a pixel's minimum is the point's key, the smallest point index wins ties.
 * Points are 21-bit cell coordinates of the hierarchy's cube. The camera: rows of a rotation in Q30 fixed point
 * and the eye in cells; camera z is the view direction. The projection keeps 14 fraction bits of cells
 * (q = c >> 16 of the Q30 product) and 8 of pixels, and divides magnitudes only (signed division rounds
 * differently between languages). */
#ifndef MV_SPLAT_H
#define MV_SPLAT_H
#include "mv_lang.h"

MV_STRUCT_BEGIN(MvSplatParams)
  mv_u32 n;            /* points in this dispatch */
  mv_u32 base;         /* index of its first point */
  mv_u32 width;
  mv_u32 height;
  mv_u32 radius;       /* half the splat's side in pixels */
  mv_u32 focal_q8;     /* focal length in pixels, 8 fraction bits */
  mv_i32 cx_q8;        /* the image centre in pixels, 8 fraction bits */
  mv_i32 cy_q8;
  mv_u32 near_q14;     /* points closer than this (cells, 14 fraction bits) are not drawn */
  mv_u32 depth_shift;  /* depth key = camera z (Q14 cells) >> depth_shift, clamped to 32 bits */
  mv_i32 eye_x;        /* the eye in cells */
  mv_i32 eye_y;
  mv_i32 eye_z;
  mv_i32 rot[9];       /* rows: camera x (right), y (up), z (forward), Q30 */
MV_STRUCT_END(MvSplatParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvSplatParams, 88);
MV_LAYOUT_AT(MvSplatParams, n, 0); MV_LAYOUT_AT(MvSplatParams, radius, 16); MV_LAYOUT_AT(MvSplatParams, cx_q8, 24);
MV_LAYOUT_AT(MvSplatParams, depth_shift, 36); MV_LAYOUT_AT(MvSplatParams, eye_x, 40); MV_LAYOUT_AT(MvSplatParams, rot, 52);
#endif

#define MV_SPLAT_EMPTY 0xffffffffu /* depth and index of a pixel no point reached */

/* Where a point lands: its pixel and depth key; visible 0 when it is behind the near plane. */
MV_STRUCT_BEGIN(MvSplatHit)
  mv_i32 px;
  mv_i32 py;
  mv_u32 key;
  mv_u32 visible;
MV_STRUCT_END(MvSplatHit)

MV_INLINE MvSplatHit mv_splat_project(mv_u32 x, mv_u32 y, mv_u32 z, MvSplatParams p) {
  MvSplatHit hit;
  hit.px = 0;
  hit.py = 0;
  hit.key = 0u;
  hit.visible = 0u;
  mv_i64 dx = MV_I64(x) - MV_I64(p.eye_x);
  mv_i64 dy = MV_I64(y) - MV_I64(p.eye_y);
  mv_i64 dz = MV_I64(z) - MV_I64(p.eye_z);
  mv_i64 cam[3];
  for (mv_u32 r = 0u; r < 3u; ++r)
    cam[r] = (MV_I64(p.rot[3u * r]) * dx + MV_I64(p.rot[3u * r + 1u]) * dy + MV_I64(p.rot[3u * r + 2u]) * dz) >> 16;
  if (cam[2] <= MV_I64(p.near_q14)) return hit;
  mv_i64 ax = cam[0] < MV_I64(0) ? -cam[0] : cam[0];
  mv_i64 ay = cam[1] < MV_I64(0) ? -cam[1] : cam[1];
  mv_i64 f = MV_I64(p.focal_q8);
  /* |camera x| / z in pixels is at most 2^23 here or the point is far off screen anyway */
  mv_i64 limit = MV_I64(1) << 23;
  mv_i64 qx = ax / cam[2] >= limit ? limit << 8 : (ax * f) / cam[2];
  mv_i64 qy = ay / cam[2] >= limit ? limit << 8 : (ay * f) / cam[2];
  if (cam[0] < MV_I64(0)) qx = -qx;
  if (cam[1] < MV_I64(0)) qy = -qy;
  hit.px = MV_I32((MV_I64(p.cx_q8) + qx) >> 8);
  hit.py = MV_I32((MV_I64(p.cy_q8) - qy) >> 8);
  mv_i64 k = cam[2] >> p.depth_shift;
  hit.key = k >= MV_I64(MV_SPLAT_EMPTY) ? MV_SPLAT_EMPTY - 1u : MV_U32(k);
  hit.visible = 1u;
  return hit;
}

/* xyz: 3 cell coordinates per point; depth, index: one word per pixel, row-major from the top. */
MV_INLINE void mv_splat(MvBufU32 xyz, MvBufU32 depth, MvBufU32 index, MvSplatParams p, bool second, mv_u32 gid,
                        mv_u32 stride) {
  mv_i32 r = MV_I32(p.radius);
  for (mv_u32 i = gid; i < p.n; i += stride) {
    MvSplatHit hit = mv_splat_project(MV_LD(xyz, 3u * i), MV_LD(xyz, 3u * i + 1u), MV_LD(xyz, 3u * i + 2u), p);
    if (hit.visible == 0u) continue;
    mv_i32 px = hit.px;
    mv_i32 py = hit.py;
    mv_u32 key = hit.key;
    if (px + r < 0 || py + r < 0 || px - r >= MV_I32(p.width) || py - r >= MV_I32(p.height)) continue;
    mv_i32 x0 = MV_MAX(px - r, 0);
    mv_i32 x1 = MV_MIN(px + r, MV_I32(p.width) - 1);
    mv_i32 y0 = MV_MAX(py - r, 0);
    mv_i32 y1 = MV_MIN(py + r, MV_I32(p.height) - 1);
    for (mv_i32 yy = y0; yy <= y1; ++yy)
      for (mv_i32 xx = x0; xx <= x1; ++xx) {
        mv_u32 at = MV_U32(yy) * p.width + MV_U32(xx);
        if (!second) MV_ATOMIC_MIN(depth, at, key);
        else if (MV_LD(depth, at) == key) MV_ATOMIC_MIN(index, at, p.base + i);
      }
  }
}

#endif
