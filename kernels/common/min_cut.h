/* Exact min-cut of a pixel-grid graph (grid_graph.h) by tiled push-relabel, rounds driven by the host.
 *
 * The grid is cut into tiles of tile x tile pixels, coloured (tx & 1) + 2 (ty & 1). One dispatch runs the
 * tiles of one colour, one work-item per tile, each walking its tile in a fixed order. Tiles of one colour
 * never touch (not even diagonally; tiles are at least 2 pixels wide), so an item may read and write its
 * pixels' neighbours in the adjacent, idle tiles without atomics: every device runs the same operations in
 * the same order and keeps the same state, bit for bit.
 * A round is a global relabel (height = distance to the sink in the residual graph), made incrementally from
 * the heights the last round left, then discharge passes:
 *   mincut_invalidate: heights that are no longer an upper bound of the distance become MV_MINCUT_INF: a
 *                    pixel keeps its height only with sink capacity or a residual edge to a lower neighbour,
 *                    so every height kept has a path of falling heights to the sink. Tiles the discharge
 *                    touched are checked first, then the tiles around each change, pass by pass.
 *   mincut_relax:    lowers heights to the distances (Gauss-Seidel sweeps inside a tile, forward then
 *                    backward, until the tile is still) in the tiles around a change, pass by pass. Starting
 *                    from upper bounds, the sweeps end at the distances exactly.
 *                    Both set flag[0] when anything changed; the host repeats passes until nothing does.
 *   mincut_active:   flag[1] is set when a pixel with excess can still reach the sink.
 *   mincut_discharge: push-relabel sweeps over a tile: push to the sink, then along admissible edges
 *                    (height one above the neighbour's), then relabel (1 + the lowest residual neighbour);
 *                    tiles without movable excess are skipped. It marks the tiles it changes as touched.
 * Heights of pixels that cannot reach the sink are MV_MINCUT_INF: such pixels never receive flow again.
 * All values are 32-bit unsigned; the host keeps the total capacity below 2^31, so nothing overflows.
 * Loops are bounded by the tile size and the sweep count, which the host keeps within lavapipe's loop cap. */
#ifndef MV_MIN_CUT_H
#define MV_MIN_CUT_H
#include "grid_graph.h"

#define MV_MINCUT_INF 0xffffffffu
/* Push-then-relabel rounds a discharge gives a pixel per visit (2: 1.05-1.21x BK at 1 MP 8-connected; 4:
 * 1.21-1.33x; 8: 1.20-1.47x; 16: no better). Each runs one loop over the pixel's edges. */
#define MV_MINCUT_ATTEMPTS 8u

MV_STRUCT_BEGIN(MvMinCutParams)
  mv_u32 width;
  mv_u32 height;
  mv_u32 conn;          /* 4 or 8 */
  mv_u32 tile;          /* tile side in pixels (>= 2) */
  mv_u32 tiles_x;       /* tiles across the grid */
  mv_u32 tiles_y;
  mv_u32 color;         /* the colour this dispatch runs, 0..3 */
  mv_u32 color_tiles_x; /* tiles of that colour across */
  mv_u32 first_tile;    /* index of this dispatch's first tile among the colour's tiles */
  mv_u32 sweeps;        /* sweeps over a tile per dispatch */
  mv_u32 stamp_now;     /* invalidate, relax: this pass's number (tile stamps count passes of every round) */
  mv_u32 stamp_since;   /* invalidate, relax: a tile runs when a stamp around it is at least this */
  mv_u32 from_touched;  /* invalidate, relax: 1 in a step's first pass, which runs the touched tiles instead */
MV_STRUCT_END(MvMinCutParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvMinCutParams, 52);
MV_LAYOUT_AT(MvMinCutParams, width, 0); MV_LAYOUT_AT(MvMinCutParams, height, 4); MV_LAYOUT_AT(MvMinCutParams, conn, 8);
MV_LAYOUT_AT(MvMinCutParams, tile, 12); MV_LAYOUT_AT(MvMinCutParams, tiles_x, 16);
MV_LAYOUT_AT(MvMinCutParams, tiles_y, 20); MV_LAYOUT_AT(MvMinCutParams, color, 24);
MV_LAYOUT_AT(MvMinCutParams, color_tiles_x, 28); MV_LAYOUT_AT(MvMinCutParams, first_tile, 32);
MV_LAYOUT_AT(MvMinCutParams, sweeps, 36); MV_LAYOUT_AT(MvMinCutParams, stamp_now, 40);
MV_LAYOUT_AT(MvMinCutParams, stamp_since, 44); MV_LAYOUT_AT(MvMinCutParams, from_touched, 48);
#endif

/* Tile t of the dispatch's colour, as tile column and row (past the grid for the colour's last tiles). */
MV_INLINE mv_u32 mv_mincut_tile_x(MvMinCutParams p, mv_u32 t) { return 2u * (t % p.color_tiles_x) + (p.color & 1u); }
MV_INLINE mv_u32 mv_mincut_tile_y(MvMinCutParams p, mv_u32 t) { return 2u * (t / p.color_tiles_x) + (p.color >> 1u); }

/* Pixel i's neighbour d is pixel i + step. An edge leaving the grid has no capacity (validate_grid_graph) and
 * never gains any (flow only moves along edges with capacity), so a neighbour is read only through an edge
 * with residual capacity and needs no bounds check. */
MV_INLINE mv_u32 mv_mincut_step(MvMinCutParams p, mv_u32 i, mv_u32 d) {
  return MV_U32(MV_I32(i) + mv_grid_dy(d) * MV_I32(p.width) + mv_grid_dx(d));
}

/* The lowest height among pixel i's neighbours across residual edges (MV_MINCUT_INF when none). Branch-free:
 * every neighbour's height is read (clamped into the grid; a step off the grid's side lands on the next row)
 * and one without residual capacity counts as unreachable. Branches on capacities mispredict half the time. */
#define MV_MINCUT_LOWER(d)                                                                                         \
  low = MV_MIN(low, MV_LD(resid, e + (d)) != 0u ? MV_LD(height, MV_MIN(mv_mincut_step(p, i, d), last)) : MV_MINCUT_INF);
MV_INLINE mv_u32 mv_mincut_lowest(MvBufU32 height, MvBufU32 resid, MvMinCutParams p, mv_u32 i) {
  mv_u32 e = i * p.conn;
  mv_u32 last = p.width * p.height - 1u;
  mv_u32 low = MV_MINCUT_INF;
  MV_MINCUT_LOWER(0u) MV_MINCUT_LOWER(1u) MV_MINCUT_LOWER(2u) MV_MINCUT_LOWER(3u)
  if (p.conn == 8u) {
    MV_MINCUT_LOWER(4u) MV_MINCUT_LOWER(5u) MV_MINCUT_LOWER(6u) MV_MINCUT_LOWER(7u)
  }
  return low;
}

/* Visits the pixels of a tile in order (forward on even sweeps, backward on odd ones), without divisions. */
#define MV_MINCUT_NEXT(s, x, y, x0, y0, x1)                                                                           \
  if (((s) & 1u) == 0u) {                                                                                          \
    if (++(x) == (x1)) { (x) = (x0); ++(y); }                                                                        \
  } else if ((x) == (x0)) { (x) = (x1) - 1u; --(y); } else { --(x); }

/* stamp[tile] = the last pass in which a height on the tile's border changed, or in which the tile was cut
 * short by the sweep count before it was still. A tile whose 3 x 3 tiles around have no stamp from
 * p.stamp_since on is still: its last run ended still and nothing it reads has changed since. */
MV_INLINE bool mv_mincut_near_change(MvBufU32 stamp, MvMinCutParams p, mv_u32 tx, mv_u32 ty) {
  bool near = false;
  for (mv_u32 k = 0u; k < 9u; ++k) {
    mv_i32 nx = MV_I32(tx) + MV_I32(k % 3u) - 1;
    mv_i32 ny = MV_I32(ty) + MV_I32(k / 3u) - 1;
    if (nx < 0 || ny < 0 || nx >= MV_I32(p.tiles_x) || ny >= MV_I32(p.tiles_y)) continue;
    if (MV_LD(stamp, MV_U32(ny) * p.tiles_x + MV_U32(nx)) >= p.stamp_since) near = true;
  }
  return near;
}

/* One pass of a global relabel's two steps over tile t (settle: mincut_invalidate or mincut_relax).
 *   invalidate: a height stays only where it has support, sink capacity or a residual edge to a lower
 *               neighbour; others become MV_MINCUT_INF. A tile it changes is marked touched, for relax.
 *   relax:      a height falls to 1 + the lowest residual neighbour (1 with sink capacity).
 * In a step's first pass (p.from_touched) the touched tiles run (relax clears the mark); a touched tile's
 * heights or edges changed since the last relabel, so invalidation stamps it for the tiles around it. */
MV_INLINE void mv_mincut_settle(MvBufU32 height, MvBufU32 sink, MvBufU32 resid, MvBufU32 flag, MvBufU32 stamp,
                                MvBufU32 touched, MvMinCutParams p, mv_u32 t, bool relax) {
  mv_u32 tx = mv_mincut_tile_x(p, t);
  mv_u32 ty = mv_mincut_tile_y(p, t);
  if (tx >= p.tiles_x || ty >= p.tiles_y) return;
  mv_u32 tile = ty * p.tiles_x + tx;
  bool border = false; /* a border height changed, or the tile is not still yet: the tiles around run again */
  bool changed_any = false;
  if (p.from_touched != 0u) {
    if (MV_LD(touched, tile) == 0u) return;
    if (relax) MV_ST(touched, tile, 0u);
    else border = true;
  } else if (!mv_mincut_near_change(stamp, p, tx, ty)) {
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
            mv_u32 low = mv_mincut_lowest(height, resid, p, i);
            if (low < h - 1u) now = low + 1u;
          }
        }
      } else if (h != MV_MINCUT_INF && MV_LD(sink, i) == 0u && mv_mincut_lowest(height, resid, p, i) >= h) {
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
    MV_ATOMIC_OR(flag, 0u, 1u);
  }
}

MV_INLINE void mv_mincut_active(MvBufU32 excess, MvBufU32 height, MvBufU32 flag, mv_u32 n, mv_u32 gid,
                                mv_u32 stride) {
  bool any = false;
  for (mv_u32 i = gid; i < n; i += stride)
    if (MV_LD(excess, i) > 0u && MV_LD(height, i) != MV_MINCUT_INF) any = true;
  if (any) MV_ATOMIC_OR(flag, 1u, 1u);
}

/* Marks tile (tx, ty) as holding excess (a push from a neighbouring tile; same-coloured tiles may mark one tile
 * at once, with the same value). */
MV_INLINE void mv_mincut_mark(MvBufU32 busy, MvBufU32 touched, MvMinCutParams p, mv_u32 x, mv_u32 y) {
  mv_u32 tile = (y / p.tile) * p.tiles_x + x / p.tile;
  MV_ATOMIC_OR(busy, tile, 1u);
  MV_ATOMIC_OR(touched, tile, 1u);
}

/* What mv_mincut_discharge_pixel did: bit d (d < 8) when it pushed to neighbour d inside the tile, which then
 * holds excess it can move; MV_MINCUT_STILL_ACTIVE when the pixel itself is left with excess it can move. */
#define MV_MINCUT_STILL_ACTIVE 0x100u

/* Pushes pixel (x, y)'s excess, relabelling it when it is left with some (MV_MINCUT_ATTEMPTS times at most). A push
 * past the tile [x0, x1) x [y0, y1) marks the neighbour's tile busy. Called only on a pixel with excess and a
 * height below MV_MINCUT_INF. */
MV_INLINE mv_u32 mv_mincut_discharge_pixel(MvBufU32 excess, MvBufU32 height, MvBufU32 sink, MvBufU32 resid,
                                         MvBufU32 busy, MvBufU32 touched, MvMinCutParams p, mv_u32 x, mv_u32 y,
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
      mv_u32 j = mv_mincut_step(p, i, d);
      if (MV_LD(height, j) + 1u != h) continue; /* MV_MINCUT_INF + 1 is 0, below every height */
      mv_u32 f = MV_MIN(e, r);
      MV_ST(resid, i * p.conn + d, r - f);
      MV_ST(resid, j * p.conn + (d ^ 1u), MV_LD(resid, j * p.conn + (d ^ 1u)) + f);
      MV_ST(excess, j, MV_LD(excess, j) + f);
      e -= f;
      mv_u32 jx = MV_U32(MV_I32(x) + mv_grid_dx(d));
      mv_u32 jy = MV_U32(MV_I32(y) + mv_grid_dy(d));
      if (jx < x0 || jx >= x1 || jy < y0 || jy >= y1) mv_mincut_mark(busy, touched, p, jx, jy);
      else done |= 1u << d; /* its height is h - 1: it can move what it got */
    }
    if (e == 0u) break;
    mv_u32 low = mv_mincut_lowest(height, resid, p, i);
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
#define MV_MINCUT_MAX_TILE 32u
#define MV_MINCUT_MASK_WORDS (MV_MINCUT_MAX_TILE * MV_MINCUT_MAX_TILE / 32u)

/* busy[tile] = 0 only when no pixel of the tile has excess it can still move: such a tile is skipped. The
 * tile's own word is rewritten at the end from what is left in it. A tile that runs, and every tile it pushes
 * into, is marked touched for the next global relabel. Sweeps alternate forward and backward; the tile is done
 * after a sweep that finds nothing to move, or after p.sweeps. */
MV_INLINE void mv_mincut_discharge(MvBufU32 excess, MvBufU32 height, MvBufU32 sink, MvBufU32 resid,
                                   MvBufU32 busy, MvBufU32 touched, MvMinCutParams p, mv_u32 t) {
  mv_u32 tx = mv_mincut_tile_x(p, t);
  mv_u32 ty = mv_mincut_tile_y(p, t);
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
      mv_u32 done = mv_mincut_discharge_pixel(excess, height, sink, resid, busy, touched, p, x0 + lx, y0 + ly, x0,
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
  MV_ST(touched, ty * p.tiles_x + tx, 1u);
}

#endif /* MV_MIN_CUT_H */
