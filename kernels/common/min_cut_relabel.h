/* The tiled push-relabel min-cut's global relabel (min_cut.h): every height becomes the pixel's distance to the
 * sink in the residual graph (MV_MINCUT_INF where there is none), computed afresh each time as a breadth-first
 * wave from the sink, and the test for pixels that still hold movable excess.
 *   min_cut_seed: per pixel, height 1 with sink capacity (the sink is at 0), MV_MINCUT_INF elsewhere.
 *   min_cut_wave: per tile (one colour a dispatch, as the discharge), a pixel's height falls to 1 + the lowest
 *                 residual neighbour until the tile is still: a work list of the tile's pixels (a bit each),
 *                 visited in scan order, forward and backward by turns; a pixel that falls puts the neighbours
 *                 in the tile that reach it back on the list. Heights only fall, from upper bounds, so the fixed point is the
 *                 distances whatever the order: every device ends with the same words. A tile whose border
 *                 fell stamps itself; the next pass runs the tiles beside a stamp, their border pixels listed
 *                 (the inside is still), so a wave crosses many levels a dispatch and only where it moves.
 * Both the wave's passes and the host's batches of them are counted in flag words (p.flag_word). */
#ifndef MV_MIN_CUT_RELABEL_H
#define MV_MIN_CUT_RELABEL_H
#include "min_cut_tiles.h"

MV_INLINE void mv_min_cut_seed(MvBufU32 height, MvBufU32 sink, mv_u32 n, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < n; i += stride) MV_ST(height, i, MV_LD(sink, i) > 0u ? 1u : MV_MINCUT_INF);
}

/* One pass of the wave over tile t. p.first_pass != 0: the first pass, every tile, with the pixels beside a
 * seed (height 1) listed, and the border's. Else a tile runs when a stamp around it is p.stamp_since or later,
 * with its border pixels listed (the inside is still), or all of its pixels when its own last run stopped at
 * its visit budget (unfinished[tile] = 1). p.sweeps bounds a run's visits to p.sweeps x the tile's pixels
 * (loop caps); a run stopped there stamps its tile. A pixel that falls lists the neighbours in the tile with a
 * residual edge to it. */
#define MV_MINCUT_LIST(lx, ly)                                                                                     \
  for (mv_u32 d = 0u; d < p.conn; ++d) {                                                                           \
    mv_i32 nx = MV_I32(lx) + mv_grid_dx(d);                                                                        \
    mv_i32 ny = MV_I32(ly) + mv_grid_dy(d);                                                                        \
    if (nx < 0 || ny < 0 || nx >= MV_I32(w) || ny >= MV_I32(h)) continue;                                          \
    mv_u32 j = MV_U32(ny) * w + MV_U32(nx);                                                                        \
    if (MV_LD(resid, ((y0 + MV_U32(ny)) * p.width + x0 + MV_U32(nx)) * p.conn + (d ^ 1u)) != 0u)                 \
      list[j >> 5] |= 1u << (j & 31u);                                                                             \
  }
MV_INLINE void mv_min_cut_wave(MvBufU32 height, MvBufU32 resid, MvBufU32 flag, MvBufU32 stamp, MvBufU32 unfinished,
                               MvMinCutParams p, mv_u32 t) {
  mv_u32 tx = mv_min_cut_tile_x(p, t);
  mv_u32 ty = mv_min_cut_tile_y(p, t);
  if (tx >= p.tiles_x || ty >= p.tiles_y) return;
  mv_u32 tile = ty * p.tiles_x + tx;
  bool first = p.first_pass != 0u;
  bool all = false;
  if (!first) {
    if (!mv_min_cut_near_change(stamp, p, tx, ty)) return;
    all = MV_LD(unfinished, tile) != 0u;
  }
  mv_u32 x0 = tx * p.tile;
  mv_u32 y0 = ty * p.tile;
  mv_u32 w = MV_MIN(x0 + p.tile, p.width) - x0;
  mv_u32 h = MV_MIN(y0 + p.tile, p.height) - y0;
  mv_u32 words = (w * h + 31u) / 32u;
  mv_u32 list[MV_MINCUT_MASK_WORDS];
  for (mv_u32 k = 0u; k < words; ++k) list[k] = 0u;
  for (mv_u32 l = 0u; l < w * h; ++l) { /* pixel l of the tile is (l % w, l / w) */
    mv_u32 lx = l % w;
    mv_u32 ly = l / w;
    if (all || lx == 0u || ly == 0u || lx + 1u == w || ly + 1u == h) list[l >> 5] |= 1u << (l & 31u);
    if (first && MV_LD(height, (y0 + ly) * p.width + x0 + lx) == 1u) {
      MV_MINCUT_LIST(lx, ly)
    }
  }
  bool border = false;
  mv_u32 visits = p.sweeps * w * h;
  mv_u32 last = w * h - 1u;
  bool any = true;
  for (mv_u32 s = 0u; any && visits > 0u; ++s) {
    any = false;
    bool forward = (s & 1u) == 0u;
    mv_u32 l = forward ? 0u : last;
    for (mv_u32 k = 0u; k <= last && visits > 0u; ++k) {
      mv_u32 wd = l >> 5;
      mv_u32 m = list[wd] & (forward ? 0xffffffffu << (l & 31u) : 0xffffffffu >> (31u - (l & 31u)));
      while (m == 0u && (forward ? wd + 1u < words : wd > 0u)) {
        wd = forward ? wd + 1u : wd - 1u;
        m = list[wd];
      }
      if (m == 0u) break;
      l = (wd << 5) | (forward ? MV_FIND_LSB(m) : MV_FIND_MSB(m));
      list[wd] &= ~(1u << (l & 31u));
      any = true;
      --visits;
      mv_u32 lx = l % w;
      mv_u32 ly = l / w;
      mv_u32 i = (y0 + ly) * p.width + x0 + lx;
      mv_u32 now = MV_LD(height, i);
      if (now > 1u) {
        mv_u32 low = mv_min_cut_lowest(height, resid, p, i);
        if (low < now - 1u) {
          MV_ST(height, i, low + 1u);
          if (lx == 0u || ly == 0u || lx + 1u == w || ly + 1u == h) border = true;
          MV_MINCUT_LIST(lx, ly)
        }
      }
      if (forward ? l == last : l == 0u) break;
      l = forward ? l + 1u : l - 1u;
    }
  }
  bool left = false;
  for (mv_u32 k = 0u; k < words; ++k)
    if (list[k] != 0u) left = true;
  MV_ST(unfinished, tile, left ? 1u : 0u);
  if (border || left) {
    MV_ST(stamp, tile, p.stamp_now);
    MV_ATOMIC_OR(flag, p.flag_word, 1u);
  }
}

MV_INLINE void mv_min_cut_active(MvBufU32 excess, MvBufU32 height, MvBufU32 flag, mv_u32 n, mv_u32 gid,
                                 mv_u32 stride) {
  bool any = false;
  for (mv_u32 i = gid; i < n; i += stride)
    if (MV_LD(excess, i) > 0u && MV_LD(height, i) != MV_MINCUT_INF) any = true;
  if (any) MV_ATOMIC_OR(flag, 1u, 1u);
}

#endif /* MV_MIN_CUT_RELABEL_H */
