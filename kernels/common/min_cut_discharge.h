/* The tiled push-relabel min-cut's discharge (min_cut.h): push-relabel sweeps over one tile, with tiles that
 * hold no movable excess skipped. */
#ifndef MV_MIN_CUT_DISCHARGE_H
#define MV_MIN_CUT_DISCHARGE_H
#include "min_cut_tiles.h"

/* Marks tile (tx, ty) as holding excess (a push from a neighbouring tile; same-coloured tiles may mark one tile
 * at once, with the same value). */
MV_INLINE void mv_min_cut_mark(MvBufU32 busy, MvMinCutParams p, mv_u32 x, mv_u32 y) {
  MV_ATOMIC_OR(busy, (y / p.tile) * p.tiles_x + x / p.tile, 1u);
}

/* What mv_min_cut_discharge_pixel did: bit d (d < 8) when it pushed to neighbour d inside the tile, which then
 * holds excess it can move; MV_MINCUT_STILL_ACTIVE when the pixel itself is left with excess it can move. */
#define MV_MINCUT_STILL_ACTIVE 0x100u

/* Pushes pixel (x, y)'s excess, relabelling it when it is left with some (MV_MINCUT_ATTEMPTS times at most). A push
 * past the tile [x0, x1) x [y0, y1) marks the neighbour's tile busy. Called only on a pixel with excess and a
 * height below MV_MINCUT_INF. */
MV_INLINE mv_u32 mv_min_cut_discharge_pixel(MvBufU32 excess, MvBufU32 height, MvBufU32 sink, MvBufU32 resid,
                                          MvBufU32 busy, MvMinCutParams p, mv_u32 x, mv_u32 y,
                                          mv_u32 x0, mv_u32 y0, mv_u32 x1, mv_u32 y1) {
  mv_u32 i = y * p.width + x;
  mv_u32 e = MV_LD(excess, i);
  mv_u32 h = MV_LD(height, i);
  mv_u32 done = 0u;
  for (mv_u32 attempt = 0u; attempt < MV_MINCUT_ATTEMPTS; ++attempt) {
    mv_u32 c = MV_LD(sink, i);
    if (c > 0u) { /* the sink is at height 0, below every pixel */
      mv_u32 f = MV_MIN(e, c);
      MV_ST(sink, i, c - f);
      e -= f;
    }
    for (mv_u32 d = 0u; d < p.conn && e > 0u; ++d) {
      mv_u32 r = MV_LD(resid, i * p.conn + d);
      if (r == 0u) continue;
      mv_u32 j = mv_min_cut_step(p, i, d);
      if (MV_LD(height, j) + 1u != h) continue; /* MV_MINCUT_INF + 1 is 0, below every height */
      mv_u32 f = MV_MIN(e, r);
      MV_ST(resid, i * p.conn + d, r - f);
      MV_ST(resid, j * p.conn + (d ^ 1u), MV_LD(resid, j * p.conn + (d ^ 1u)) + f);
      MV_ST(excess, j, MV_LD(excess, j) + f);
      e -= f;
      mv_u32 jx = MV_U32(MV_I32(x) + mv_grid_dx(d));
      mv_u32 jy = MV_U32(MV_I32(y) + mv_grid_dy(d));
      if (jx < x0 || jx >= x1 || jy < y0 || jy >= y1) mv_min_cut_mark(busy, p, jx, jy);
      else done |= 1u << d; /* its height is h - 1: it can move what it got */
    }
    if (e == 0u) break;
    mv_u32 low = mv_min_cut_lowest(height, resid, p, i);
    h = low >= MV_MINCUT_INF - 1u ? MV_MINCUT_INF : low + 1u;
    if (h == MV_MINCUT_INF) break;
  }
  MV_ST(excess, i, e);
  MV_ST(height, i, h);
  return e > 0u && h != MV_MINCUT_INF ? done | MV_MINCUT_STILL_ACTIVE : done;
}

/* The tile's pixels that hold excess they can move (excess above 0, height below MV_MINCUT_INF), one bit per
 * pixel at (y - y0) * tile + (x - x0): a sweep visits these alone, in the order of a full scan of the tile, so
 * it does what a scan visiting every pixel did, without reading the others. The bits change only where this
 * item moves excess: tiles of one colour never touch. */

/* busy[tile] = 0 only when no pixel of the tile has excess it can still move: such a tile is skipped. The
 * tile's own word is rewritten at the end from what is left in it. Sweeps alternate forward and backward; the tile is done
 * after a sweep that finds nothing to move, or after p.sweeps. */
MV_INLINE void mv_min_cut_discharge(MvBufU32 excess, MvBufU32 height, MvBufU32 sink, MvBufU32 resid,
                                    MvBufU32 busy, MvMinCutParams p, mv_u32 t) {
  mv_u32 tx = mv_min_cut_tile_x(p, t);
  mv_u32 ty = mv_min_cut_tile_y(p, t);
  if (tx >= p.tiles_x || ty >= p.tiles_y) return;
  if (MV_LD(busy, ty * p.tiles_x + tx) == 0u) return;
  mv_u32 x0 = tx * p.tile;
  mv_u32 y0 = ty * p.tile;
  mv_u32 x1 = MV_MIN(x0 + p.tile, p.width);
  mv_u32 y1 = MV_MIN(y0 + p.tile, p.height);
  mv_u32 words = (p.tile * p.tile + 31u) / 32u;
  mv_u32 movable[MV_MINCUT_MASK_WORDS];
  for (mv_u32 w = 0u; w < words; ++w) movable[w] = 0u;
  bool any = false;
  for (mv_u32 y = y0; y < y1; ++y)
    for (mv_u32 x = x0; x < x1; ++x) {
      mv_u32 i = y * p.width + x;
      if (MV_LD(excess, i) > 0u && MV_LD(height, i) != MV_MINCUT_INF) {
        mv_u32 l = (y - y0) * p.tile + (x - x0);
        movable[l >> 5] |= 1u << (l & 31u);
        any = true;
      }
    }
  mv_u32 last = p.tile * p.tile - 1u;
  for (mv_u32 s = 0u; s < p.sweeps && any; ++s) {
    any = false;
    bool forward = (s & 1u) == 0u;
    mv_u32 l = forward ? 0u : last; /* where the search for the next pixel starts */
    for (mv_u32 k = 0u; k <= last; ++k) {
      /* the next marked pixel at or after l (forward), at or before it (backward) */
      mv_u32 w = l >> 5;
      mv_u32 m = movable[w] & (forward ? 0xffffffffu << (l & 31u) : 0xffffffffu >> (31u - (l & 31u)));
      while (m == 0u && (forward ? w + 1u < words : w > 0u)) {
        w = forward ? w + 1u : w - 1u;
        m = movable[w];
      }
      if (m == 0u) break;
      l = (w << 5) | (forward ? MV_FIND_LSB(m) : MV_FIND_MSB(m));
      any = true;
      mv_u32 lx = l % p.tile;
      mv_u32 ly = l / p.tile;
      mv_u32 done = mv_min_cut_discharge_pixel(excess, height, sink, resid, busy, p, x0 + lx, y0 + ly, x0,
                                               y0, x1, y1);
      if ((done & MV_MINCUT_STILL_ACTIVE) == 0u) movable[w] &= ~(1u << (l & 31u));
      for (mv_u32 d = 0u; d < p.conn; ++d) {
        if ((done & (1u << d)) == 0u) continue;
        mv_u32 j = MV_U32(MV_I32(l) + mv_grid_dy(d) * MV_I32(p.tile) + mv_grid_dx(d));
        movable[j >> 5] |= 1u << (j & 31u);
      }
      if (forward ? l == last : l == 0u) break;
      l = forward ? l + 1u : l - 1u;
    }
  }
  mv_u32 left = 0u;
  for (mv_u32 w = 0u; w < words; ++w)
    if (movable[w] != 0u) left = 1u;
  MV_ST(busy, ty * p.tiles_x + tx, left);
}

#endif /* MV_MIN_CUT_DISCHARGE_H */
