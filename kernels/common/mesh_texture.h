/* The colour at a point of a mesh's triangle (docs/colour.md), written once for the host, OpenCL C and GLSL: its
 * vertex colours interpolated there, or its texture sampled bilinearly at its interpolated texture coordinates;
 * every channel rounded half up. mesh_colour.h finds the point. */
#ifndef MV_MESH_TEXTURE_H
#define MV_MESH_TEXTURE_H
#include "floor64.h"

#define MV_MESH_ATTR_WORDS 12u /* per triangle: 3 vertex colours, 6 texture coordinates, the texture, 2 spare */
#define MV_NO_TEXTURE 0xffffffffu

/* floor(c + 0.5) clamped to [0, 255]: a channel rounded half up (truncation is floor where it is not clamped). */
MV_INLINE mv_u32 mv_channel_byte(mv_f64 c) {
  return c + 0.5 < 1.0 ? 0u : c + 0.5 >= 255.0 ? 255u : MV_U32(c + 0.5);
}

/* One channel of the colour at weights (1 - wb - wc, wb, wc) of vertex colours ca, cb, cc (0xBBGGRR), rounded. */
MV_INLINE mv_u32 mv_mesh_channel(mv_u32 ca, mv_u32 cb, mv_u32 cc, mv_u32 shift, mv_f64 wb, mv_f64 wc) {
  MV_PRECISE mv_f64 x = MV_F64((ca >> shift) & 255u) * (1.0 - wb - wc) + MV_F64((cb >> shift) & 255u) * wb +
                        MV_F64((cc >> shift) & 255u) * wc;
  return mv_channel_byte(x);
}

/* Texture `tex` sampled bilinearly at (u, v) (v = 0 at the bottom row; repeating; channels rounded half up): texel
 * centres at half-integers, the four around the point weighted by their distances, wrapping at the edges. `texels`:
 * the count, then per texture its first texel's word, width and height, then the texels (0xBBGGRR, top row first). */
MV_INLINE mv_u32 mv_texture_rgb(MvBufU32 texels, mv_u32 tex, mv_f64 u, mv_f64 v) {
  mv_u32 base = MV_LD(texels, 1u + 3u * tex), w = MV_LD(texels, 2u + 3u * tex), h = MV_LD(texels, 3u + 3u * tex);
  MV_PRECISE mv_f64 x = (u - mv_floor64(u)) * MV_F64(w) - 0.5, y = (1.0 - (v - mv_floor64(v))) * MV_F64(h) - 0.5;
  mv_f64 x0 = mv_floor64(x), y0 = mv_floor64(y);
  MV_PRECISE mv_f64 fx = x - x0, fy = y - y0;
  /* x0 is in [-1, w - 1] and y0 in [-1, h - 1]; the clamps only keep a NaN coordinate inside the texture. */
  mv_i32 ix = MV_I32(x0), iy = MV_I32(y0);
  mv_u32 xa = ix < 0 ? w - 1u : MV_MIN(MV_U32(ix), w - 1u), ya = iy < 0 ? h - 1u : MV_MIN(MV_U32(iy), h - 1u);
  mv_u32 xb = ix + 1 >= MV_I32(w) ? 0u : MV_MIN(MV_U32(ix + 1), w - 1u);
  mv_u32 yb = iy + 1 >= MV_I32(h) ? 0u : MV_MIN(MV_U32(iy + 1), h - 1u);
  mv_u32 t00 = MV_LD(texels, base + ya * w + xa), t10 = MV_LD(texels, base + ya * w + xb);
  mv_u32 t01 = MV_LD(texels, base + yb * w + xa), t11 = MV_LD(texels, base + yb * w + xb), rgb = 0u;
  for (mv_u32 shift = 0u; shift < 24u; shift += 8u) {
    mv_f64 c00 = MV_F64((t00 >> shift) & 255u), c10 = MV_F64((t10 >> shift) & 255u);
    mv_f64 c01 = MV_F64((t01 >> shift) & 255u), c11 = MV_F64((t11 >> shift) & 255u);
    MV_PRECISE mv_f64 c = (c00 * (1.0 - fx) + c10 * fx) * (1.0 - fy) + (c01 * (1.0 - fx) + c11 * fx) * fy;
    rgb |= mv_channel_byte(c) << shift;
  }
  return rgb;
}

/* The colour (0xBBGGRR) of the batch's triangle t at weights (1 - wb - wc, wb, wc): its vertex colours
 * interpolated, or its texture sampled at its interpolated coordinates. `attr`: MV_MESH_ATTR_WORDS a triangle (3
 * vertex colours, 6 texture coordinates as float bits, the texture). */
MV_INLINE mv_u32 mv_mesh_colour_at(MvBufU32 attr, MvBufU32 texels, mv_u32 t, mv_f64 wb, mv_f64 wc) {
  mv_u32 a = MV_MESH_ATTR_WORDS * t, tex = MV_LD(attr, a + 9u);
  if (tex == MV_NO_TEXTURE) {
    mv_u32 ca = MV_LD(attr, a), cb = MV_LD(attr, a + 1u), cc = MV_LD(attr, a + 2u);
    return mv_mesh_channel(ca, cb, cc, 0u, wb, wc) | (mv_mesh_channel(ca, cb, cc, 8u, wb, wc) << 8) |
           (mv_mesh_channel(ca, cb, cc, 16u, wb, wc) << 16);
  }
  MV_PRECISE mv_f64 wa = 1.0 - wb - wc;
  MV_PRECISE mv_f64 u = MV_F64(MV_BITSF(MV_LD(attr, a + 3u))) * wa + MV_F64(MV_BITSF(MV_LD(attr, a + 5u))) * wb +
                        MV_F64(MV_BITSF(MV_LD(attr, a + 7u))) * wc;
  MV_PRECISE mv_f64 v = MV_F64(MV_BITSF(MV_LD(attr, a + 4u))) * wa + MV_F64(MV_BITSF(MV_LD(attr, a + 6u))) * wb +
                        MV_F64(MV_BITSF(MV_LD(attr, a + 8u))) * wc;
  return mv_texture_rgb(texels, tex, u, v);
}

#endif /* MV_MESH_TEXTURE_H */
