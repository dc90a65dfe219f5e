/* Mask post-processing (Jaspe Villanueva's thesis, 2018, ch. 3: a 5x5 median, then erosion with an
 * octagon), one pixel per work-item of a 2-D launch. Masks are one 32-bit word per pixel, 0 or 1.
 *   mask_median5: 1 where at least 13 of the 25 pixels around are 1 (the median of binary values); pixels
 *                 past the border repeat the nearest edge pixel.
 *   mask_erode:   1 where the pixel and every pixel of the octagon of radius r around it are 1: offsets with
 *                 |dx| <= r, |dy| <= r and (|dx| + |dy|)^2 <= 2 r^2 (a regular octagon of inradius r).
 *                 Offsets past the border do not count, so the image edge does not erode the mask.
 * The loops are bounded: 25 taps, (2r + 1)^2 taps with r <= MV_MASK_MAX_RADIUS. */
#ifndef MV_MASK_POST_H
#define MV_MASK_POST_H
#include "mv_lang.h"

#define MV_MASK_MAX_RADIUS 32u

MV_STRUCT_BEGIN(MvMaskPostParams)
  mv_u32 width;
  mv_u32 height;
  mv_u32 radius;
  mv_u32 pad0;
MV_STRUCT_END(MvMaskPostParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvMaskPostParams, 16);
MV_LAYOUT_AT(MvMaskPostParams, width, 0); MV_LAYOUT_AT(MvMaskPostParams, height, 4);
MV_LAYOUT_AT(MvMaskPostParams, radius, 8); MV_LAYOUT_AT(MvMaskPostParams, pad0, 12);
#endif

MV_INLINE void mv_mask_median5(MvBufU32 src, MvBufU32 dst, MvMaskPostParams p, mv_u32 x, mv_u32 y) {
  if (x >= p.width || y >= p.height) return;
  mv_u32 ones = 0u;
  for (mv_u32 k = 0u; k < 25u; ++k) {
    mv_i32 sx = MV_I32(x) + MV_I32(k % 5u) - 2;
    mv_i32 sy = MV_I32(y) + MV_I32(k / 5u) - 2;
    sx = MV_MAX(0, MV_MIN(sx, MV_I32(p.width) - 1));
    sy = MV_MAX(0, MV_MIN(sy, MV_I32(p.height) - 1));
    ones += MV_LD(src, MV_U32(sy) * p.width + MV_U32(sx));
  }
  MV_ST(dst, y * p.width + x, ones >= 13u ? 1u : 0u);
}

MV_INLINE void mv_mask_erode(MvBufU32 src, MvBufU32 dst, MvMaskPostParams p, mv_u32 x, mv_u32 y) {
  if (x >= p.width || y >= p.height) return;
  mv_u32 keep = MV_LD(src, y * p.width + x);
  mv_i32 r = MV_I32(p.radius);
  mv_u32 side = 2u * p.radius + 1u;
  for (mv_u32 k = 0u; k < side * side && keep != 0u; ++k) {
    mv_i32 dx = MV_I32(k % side) - r;
    mv_i32 dy = MV_I32(k / side) - r;
    mv_i32 l1 = (dx < 0 ? -dx : dx) + (dy < 0 ? -dy : dy);
    if (l1 * l1 > 2 * r * r) continue;
    mv_i32 sx = MV_I32(x) + dx;
    mv_i32 sy = MV_I32(y) + dy;
    if (sx < 0 || sy < 0 || sx >= MV_I32(p.width) || sy >= MV_I32(p.height)) continue;
    if (MV_LD(src, MV_U32(sy) * p.width + MV_U32(sx)) == 0u) keep = 0u;
  }
  MV_ST(dst, y * p.width + x, keep);
}

#endif /* MV_MASK_POST_H */
