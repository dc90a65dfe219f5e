/* The tiled push-relabel min-cut's shared vocabulary (min_cut.h): its parameters, the tile colouring and
 * pixel order, neighbour steps and the lowest residual neighbour. Used by both of its passes, the global
 * relabel (min_cut_relabel.h) and the discharge (min_cut_discharge.h). */
#ifndef MV_MIN_CUT_TILES_H
#define MV_MIN_CUT_TILES_H
#include "grid_graph.h"

#define MV_MINCUT_INF 0xffffffffu
/* Push-then-relabel rounds a discharge gives a pixel per visit (2: 1.05-1.21x BK at 1 MP 8-connected; 4:
 * 1.21-1.33x; 8: 1.20-1.47x; 16: no better). Each runs one loop over the pixel's edges. */
#define MV_MINCUT_ATTEMPTS 8u

/* The largest tile: a pass keeps a bit per pixel of its tile (a work list) in MV_MINCUT_MASK_WORDS words. */
#define MV_MINCUT_MAX_TILE 32u
#define MV_MINCUT_MASK_WORDS (MV_MINCUT_MAX_TILE * MV_MINCUT_MAX_TILE / 32u)

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
  mv_u32 stamp_now;     /* wave: this pass's number (tile stamps count the passes of every relabel) */
  mv_u32 stamp_since;   /* wave: a tile runs when a stamp around it is at least this */
  mv_u32 first_pass;  /* wave: 1 in a relabel's first pass, which runs every tile and pixel */
  mv_u32 flag_word;     /* wave: the flag word this pass sets when a border fell (2 on) */
MV_STRUCT_END(MvMinCutParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvMinCutParams, 56);
MV_LAYOUT_AT(MvMinCutParams, width, 0); MV_LAYOUT_AT(MvMinCutParams, height, 4); MV_LAYOUT_AT(MvMinCutParams, conn, 8);
MV_LAYOUT_AT(MvMinCutParams, tile, 12); MV_LAYOUT_AT(MvMinCutParams, tiles_x, 16);
MV_LAYOUT_AT(MvMinCutParams, tiles_y, 20); MV_LAYOUT_AT(MvMinCutParams, color, 24);
MV_LAYOUT_AT(MvMinCutParams, color_tiles_x, 28); MV_LAYOUT_AT(MvMinCutParams, first_tile, 32);
MV_LAYOUT_AT(MvMinCutParams, sweeps, 36); MV_LAYOUT_AT(MvMinCutParams, stamp_now, 40);
MV_LAYOUT_AT(MvMinCutParams, stamp_since, 44); MV_LAYOUT_AT(MvMinCutParams, first_pass, 48);
MV_LAYOUT_AT(MvMinCutParams, flag_word, 52);
#endif

/* Tile t of the dispatch's colour, as tile column and row (past the grid for the colour's last tiles). */
MV_INLINE mv_u32 mv_min_cut_tile_x(MvMinCutParams p, mv_u32 t) { return 2u * (t % p.color_tiles_x) + (p.color & 1u); }
MV_INLINE mv_u32 mv_min_cut_tile_y(MvMinCutParams p, mv_u32 t) { return 2u * (t / p.color_tiles_x) + (p.color >> 1u); }

/* Pixel i's neighbour d is pixel i + step. An edge leaving the grid has no capacity (validate_grid_graph) and
 * never gains any (flow only moves along edges with capacity), so a neighbour is read only through an edge
 * with residual capacity and needs no bounds check. */
MV_INLINE mv_u32 mv_min_cut_step(MvMinCutParams p, mv_u32 i, mv_u32 d) {
  return MV_U32(MV_I32(i) + mv_grid_dy(d) * MV_I32(p.width) + mv_grid_dx(d));
}

/* The lowest height among pixel i's neighbours across residual edges (MV_MINCUT_INF when none). Branch-free:
 * every neighbour's height is read (clamped into the grid; a step off the grid's side lands on the next row)
 * and one without residual capacity counts as unreachable. Branches on capacities mispredict half the time. */
#define MV_MINCUT_LOWER(d)                                                                                         \
  low = MV_MIN(low, MV_LD(resid, e + (d)) != 0u ? MV_LD(height, MV_MIN(mv_min_cut_step(p, i, d), last))            \
                                                : MV_MINCUT_INF);
MV_INLINE mv_u32 mv_min_cut_lowest(MvBufU32 height, MvBufU32 resid, MvMinCutParams p, mv_u32 i) {
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

/* stamp[tile] = the last pass in which a height on the tile's border fell, or in which the tile was cut
 * short by its visit budget before it was still. A tile whose 3 x 3 tiles around have no stamp from
 * p.stamp_since on is still: its last run ended still and nothing it reads has changed since. */
MV_INLINE bool mv_min_cut_near_change(MvBufU32 stamp, MvMinCutParams p, mv_u32 tx, mv_u32 ty) {
  bool near = false;
  for (mv_u32 k = 0u; k < 9u; ++k) {
    mv_i32 nx = MV_I32(tx) + MV_I32(k % 3u) - 1;
    mv_i32 ny = MV_I32(ty) + MV_I32(k / 3u) - 1;
    if (nx < 0 || ny < 0 || nx >= MV_I32(p.tiles_x) || ny >= MV_I32(p.tiles_y)) continue;
    if (MV_LD(stamp, MV_U32(ny) * p.tiles_x + MV_U32(nx)) >= p.stamp_since) near = true;
  }
  return near;
}

#endif /* MV_MIN_CUT_TILES_H */
