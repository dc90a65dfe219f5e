/* Pixel-grid graphs for min-cut (masks): the neighbour numbering the host (GridGraph, the Boost reference)
 * and the min-cut kernels share. Pixel i = y * width + x; its edge d leads to (x + dx(d), y + dy(d)):
 *   d: 0 (+1, 0)  1 (-1, 0)  2 (0, +1)  3 (0, -1)   -- 4-connected uses d < 4
 *      4 (+1,+1)  5 (-1,-1)  6 (+1,-1)  7 (-1,+1)   -- 8-connected adds the diagonals
 * so the reverse of edge d is edge d ^ 1. Capacities are stored per pixel: edges[i * connectivity + d]. */
#ifndef MV_GRID_GRAPH_H
#define MV_GRID_GRAPH_H
#include "mv_lang.h"

MV_INLINE mv_i32 mv_grid_dx(mv_u32 d) {
  return (d == 0u || d == 4u || d == 6u) ? 1 : ((d == 1u || d == 5u || d == 7u) ? -1 : 0);
}
MV_INLINE mv_i32 mv_grid_dy(mv_u32 d) {
  return (d == 2u || d == 4u || d == 7u) ? 1 : ((d == 3u || d == 5u || d == 6u) ? -1 : 0);
}

#endif /* MV_GRID_GRAPH_H */
