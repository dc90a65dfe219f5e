/* The tiled push-relabel min-cut's global relabel (min_cut.h): the invalidation and relaxation passes that
 * bring the heights to the distances to the sink, and the test for pixels that still hold movable excess. */
#ifndef MV_MIN_CUT_RELABEL_H
#define MV_MIN_CUT_RELABEL_H
#include "min_cut_tiles.h"

/* One pass of a global relabel's two steps over tile t (settle: min_cut_invalidate or min_cut_relax).
 *   invalidate: a height stays only where it has support, sink capacity or a residual edge to a lower
 *               neighbour; others become MV_MINCUT_INF. A tile it changes is marked touched, for relax.
 *   relax:      a height falls to 1 + the lowest residual neighbour (1 with sink capacity).
 * In a step's first pass (p.from_touched) the touched tiles run (relax clears the mark); a touched tile's
 * heights or edges changed since the last relabel, so invalidation stamps it for the tiles around it. */
MV_INLINE void mv_min_cut_settle(MvBufU32 height, MvBufU32 sink, MvBufU32 resid, MvBufU32 flag, MvBufU32 stamp,
                                 MvBufU32 touched, MvMinCutParams p, mv_u32 t, bool relax) {
  mv_u32 tx = mv_min_cut_tile_x(p, t);
  mv_u32 ty = mv_min_cut_tile_y(p, t);
  if (tx >= p.tiles_x || ty >= p.tiles_y) return;
  mv_u32 tile = ty * p.tiles_x + tx;
  bool border = false; /* a border height changed, or the tile is not still yet: the tiles around run again */
  bool changed_any = false;
  if (p.from_touched != 0u) {
    if (MV_LD(touched, tile) == 0u) return;
    if (relax) MV_ST(touched, tile, 0u);
    else border = true;
  } else if (!mv_min_cut_near_change(stamp, p, tx, ty)) {
    return;
  }
  mv_u32 x0 = tx * p.tile;
  mv_u32 y0 = ty * p.tile;
  mv_u32 x1 = MV_MIN(x0 + p.tile, p.width);
  mv_u32 y1 = MV_MIN(y0 + p.tile, p.height);
  mv_u32 count = (x1 - x0) * (y1 - y0);
  bool changed = false;
  for (mv_u32 s = 0u; s < p.sweeps; ++s) {
    changed = false;
    mv_u32 x = (s & 1u) != 0u ? x1 - 1u : x0;
    mv_u32 y = (s & 1u) != 0u ? y1 - 1u : y0;
    for (mv_u32 k = 0u; k < count; ++k) {
      mv_u32 i = y * p.width + x;
      mv_u32 h = MV_LD(height, i);
      mv_u32 now = h;
      if (relax) {
        if (h > 1u) {
          if (MV_LD(sink, i) > 0u) {
            now = 1u;
          } else {
            mv_u32 low = mv_min_cut_lowest(height, resid, p, i);
            if (low < h - 1u) now = low + 1u;
          }
        }
      } else if (h != MV_MINCUT_INF && MV_LD(sink, i) == 0u && mv_min_cut_lowest(height, resid, p, i) >= h) {
        now = MV_MINCUT_INF;
      }
      if (now != h) {
        MV_ST(height, i, now);
        changed = true;
        if (x == x0 || y == y0 || x + 1u == x1 || y + 1u == y1) border = true;
      }
      MV_MINCUT_NEXT(s, x, y, x0, y0, x1)
    }
    if (!changed) break;
    changed_any = true;
  }
  if (changed) border = true; /* cut short by the sweep count */
  if (changed_any && !relax) MV_ST(touched, tile, 1u);
  if (border) {
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
