/* The OMiCroN builder's representatives (host side: host/core/points/omicron.cpp, through point_kernels.cpp): for
 * each parent a level gives its children, the points it keeps, one per occupied cell of its sub-grid.
 *   omicron_rep_count:  per parent (a group of candidates in Morton order), the occupied cells of its sub-grid,
 *                       capped: how many representatives it keeps;
 *   omicron_rep_select: per parent, the candidate nearest each kept cell's centre (the first of equals).
 * Everything is integer arithmetic on the Morton codes, so every device picks the same points. */
#ifndef MV_OMICRON_H
#define MV_OMICRON_H
#include "points.h"

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

/* Parent g's candidates are codes[bounds[g], bounds[g + 1]), sorted. cells[g] = occupied cells, kept[g] = how
 * many it keeps. */
MV_INLINE void mv_omicron_rep_count(MvBufU64 codes, MvBufU32 bounds, MvBufU32 cells, MvBufU32 kept,
                                    MvPointParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 g = gid; g < p.n; g += stride) {
    mv_u32 b = MV_LD(bounds, g);
    mv_u32 e = MV_LD(bounds, g + 1u);
    mv_u32 count = 0u;
    for (mv_u32 i = b; i < e; ++i)
      if (i == b || (MV_LD(codes, i) >> p.cell_bits) != (MV_LD(codes, i - 1u) >> p.cell_bits)) count += 1u;
    MV_ST(cells, g, count);
    MV_ST(kept, g, MV_MIN(count, p.cap));
  }
}

/* dst[offsets[g] + k] = the candidate position (an index into codes) of parent g's k-th kept cell. */
MV_INLINE void mv_omicron_rep_select(MvBufU64 codes, MvBufU32 bounds, MvBufU32 cells, MvBufU32 offsets,
                                     MvBufU32 dst, MvPointParams p, mv_u32 gid, mv_u32 stride) {
  for (mv_u32 g = gid; g < p.n; g += stride) {
    mv_u32 b = MV_LD(bounds, g);
    mv_u32 e = MV_LD(bounds, g + 1u);
    mv_u32 total = MV_LD(cells, g);
    mv_u32 o = MV_LD(offsets, g);
    if (e == b) continue;
    mv_u32 j = 0u;
    mv_u32 best = b;
    mv_u64 best_d = mv_rep_distance(MV_LD(codes, b), p.cell_bits);
    for (mv_u32 i = b + 1u; i <= e; ++i) {
      bool new_cell = i == e || (MV_LD(codes, i) >> p.cell_bits) != (MV_LD(codes, i - 1u) >> p.cell_bits);
      if (new_cell) {
        if (mv_rep_keeps(j, total, p.cap)) {
          MV_ST(dst, o, best);
          o += 1u;
        }
        j += 1u;
        if (i < e) {
          best = i;
          best_d = mv_rep_distance(MV_LD(codes, i), p.cell_bits);
        }
      } else {
        mv_u64 d = mv_rep_distance(MV_LD(codes, i), p.cell_bits);
        if (d < best_d) {
          best = i;
          best_d = d;
        }
      }
    }
  }
}

#endif /* MV_OMICRON_H */
