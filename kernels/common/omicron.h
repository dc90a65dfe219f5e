/* The OMiCroN builder's representatives (host side: host/core/points/omicron_representatives.cpp): for each
 * parent a level gives its children, the points it keeps, one per occupied cell of its sub-grid. A batch's
 * candidates are the parents' candidates one after another, each parent's sorted: its sub-grid cells (code >>
 * cell_bits) are runs, which also break where a parent starts, so the cells are runs of the whole batch
 * (segmented.h) and every step is spread over candidates or cells, whatever a parent holds:
 *   omicron_rep_heads:    sets the cell head flag where each parent starts;
 *   omicron_rep_distance: per candidate, its distance to its cell's centre (then a segmented arg-min per cell);
 *   omicron_rep_keep:     per cell, whether its parent keeps it (at most cap cells per parent, spread evenly);
 *   omicron_rep_compact:  the kept cells' nearest candidates, in order (positions from a scan of the keep flags);
 *   omicron_rep_offsets:  per parent, where its representatives start.
 * Everything is integer arithmetic on the Morton codes, so every device picks the same points. */
#ifndef MV_OMICRON_H
#define MV_OMICRON_H
#include "mv_lang.h"
#include "morton.h"

MV_STRUCT_BEGIN(MvRepParams)
  mv_u32 n;          /* candidates in the batch */
  mv_u32 cells;      /* occupied sub-grid cells in the batch */
  mv_u32 groups;     /* parents in the batch */
  mv_u32 cell_bits;  /* 3 x the bits per axis below a sub-grid cell (a cell id is code >> cell_bits) */
  mv_u32 cap;        /* most representatives per parent */
  mv_u32 pad0;
MV_STRUCT_END(MvRepParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvRepParams, 24);
MV_LAYOUT_AT(MvRepParams, n, 0); MV_LAYOUT_AT(MvRepParams, cells, 4); MV_LAYOUT_AT(MvRepParams, groups, 8);
MV_LAYOUT_AT(MvRepParams, cell_bits, 12); MV_LAYOUT_AT(MvRepParams, cap, 16); MV_LAYOUT_AT(MvRepParams, pad0, 20);
#endif

/* Squared distance, in units of half a finest cell, from the centre of code's finest cell to the centre of the
 * sub-grid cell holding it (side 2^(cell_bits / 3) finest cells). */
MV_INLINE mv_u64 mv_rep_distance(mv_u64 code, mv_u32 cell_bits) {
  mv_u32 side = 1u << (cell_bits / 3u);
  mv_u64 d2 = MV_U64(0u);
  for (mv_u32 a = 0u; a < 3u; ++a) {
    mv_u32 c = mv_morton3_64_axis(code, a) & (side - 1u);
    mv_u64 d = MV_U64(2u * c + 1u) >= MV_U64(side) ? MV_U64(2u * c + 1u) - MV_U64(side) : MV_U64(side) - MV_U64(2u * c + 1u);
    d2 += d * d;
  }
  return d2;
}

/* Of `cells` occupied cells, cell j is kept when it moves floor(j * cap / cells): exactly min(cells, cap) cells,
 * spread evenly along the Morton order. */
MV_INLINE bool mv_rep_keeps(mv_u32 j, mv_u32 cells, mv_u32 cap) {
  if (cells <= cap) return true;
  return (MV_U64(j + 1u) * MV_U64(cap)) / MV_U64(cells) > (MV_U64(j) * MV_U64(cap)) / MV_U64(cells);
}

MV_INLINE void mv_omicron_rep_heads(MvBufU32 bounds, MvBufU32 heads, MvRepParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 g = gid; g < p.groups; g += stride) {
    mv_u32 b = MV_LD(bounds, g);
    if (b < p.n) MV_ST(heads, b, 1u);
  }
}

MV_INLINE void mv_omicron_rep_distance(MvBufU64 codes, MvBufU64 dist, MvRepParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 i = gid; i < p.n; i += stride) MV_ST(dist, i, mv_rep_distance(MV_LD(codes, i), p.cell_bits));
}

/* Parent g's candidates are [bounds[g], bounds[g + 1]); e is the cells' segmentation of the candidates and
 * starts their first candidates. keep[c] = 1 where cell c is kept. The parent of a cell is found by binary
 * search over the bounds (at most 32 steps). */
MV_INLINE void mv_omicron_rep_keep(MvBufU32 bounds, MvBufU32 e, MvBufU32 starts, MvBufU32 keep, MvRepParams p,
                                   mv_u32 gid, mv_u32 stride) {
  for (mv_u32 c = gid; c < p.cells; c += stride) {
    mv_u32 at = MV_LD(starts, c);
    mv_u32 lo = 0u;
    mv_u32 hi = p.groups;  /* the parent is the last g < groups with bounds[g] <= at */
    while (hi - lo > 1u) {
      mv_u32 mid = (lo + hi) / 2u;
      if (MV_LD(bounds, mid) <= at) lo = mid;
      else hi = mid;
    }
    mv_u32 first = MV_LD(e, MV_LD(bounds, lo));
    mv_u32 cells = MV_LD(e, MV_LD(bounds, lo + 1u)) - first;
    MV_ST(keep, c, mv_rep_keeps(c - first, cells, p.cap) ? 1u : 0u);
  }
}

/* dst[pos[c]] = nearest[c] for every kept cell c. */
MV_INLINE void mv_omicron_rep_compact(MvBufU32 keep, MvBufU32 pos, MvBufU32 nearest, MvBufU32 dst, MvRepParams p,
                                      mv_u32 gid, mv_u32 stride) {
  for (mv_u32 c = gid; c < p.cells; c += stride)
    if (MV_LD(keep, c) != 0u) MV_ST(dst, MV_LD(pos, c), MV_LD(nearest, c));
}

/* offsets[g] = pos[first cell of parent g], for g = 0 .. groups (the last: the batch's total). */
MV_INLINE void mv_omicron_rep_offsets(MvBufU32 bounds, MvBufU32 e, MvBufU32 pos, MvBufU32 offsets, MvRepParams p,
                                      mv_u32 gid, mv_u32 stride) {
  for (mv_u32 g = gid; g <= p.groups; g += stride) MV_ST(offsets, g, MV_LD(pos, MV_LD(e, MV_LD(bounds, g))));
}

#endif /* MV_OMICRON_H */
