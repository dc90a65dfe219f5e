/* Thin (6-separating) triangle / voxel test of Schwarz & Seidel 2010 ("Fast parallel surface and solid
 * voxelization on GPUs", section 3.2), against the voxel's centre c = (i, j, k) + 1/2:
 *  - plane: the triangle's plane meets the line through c along the normal's dominant axis d (ties go to the
 *    later axis) within [c_d - 1/2, c_d + 1/2): half-open like the grid, so a triangle lying in the plane
 *    x = i sets voxel i only (the grid's top face belongs to the last voxel, as everywhere);
 *  - projections: along every axis a whose normal component n_a is non-zero, the triangle's projection meets
 *    the L1 ball of radius 1/2 around c's projection: each edge function, oriented by the sign of n_a, is
 *    offset by 1/2 * max(|n_e,u|, |n_e,v|) (the ball's support along the edge normal) and must be >= 0.
 * Candidates are the voxels of the triangle's bounding box (voxelize.h). Decisive, so written once for every
 * language and evaluated in double with a fixed order and no contraction, like tri_box.h. A degenerate
 * triangle (zero normal) sets nothing. */
#ifndef MV_TRI_THIN_H
#define MV_TRI_THIN_H
#include "mv_lang.h"

/* Edge (p, q) -> r in one projection (u, v), oriented by s = sign of the dropped normal component: is
 * the centre (the origin, vertices are relative to it) inside the edge's half-plane grown by the ball? */
MV_INLINE bool mv_thin_edge(mv_f64 pu, mv_f64 pv, mv_f64 qu, mv_f64 qv, mv_f64 s) {
  MV_PRECISE mv_f64 nu = -(qv - pv) * s;
  MV_PRECISE mv_f64 nv = (qu - pu) * s;
  MV_PRECISE mv_f64 f = -(nu * pu + nv * pv) + 0.5 * MV_FMAX(MV_FABS(nu), MV_FABS(nv));
  return f >= 0.0;
}

/* The triangle's projection dropping axis a (cyclic order: x -> (y, z), y -> (z, x), z -> (x, y)). */
MV_INLINE bool mv_thin_projection(mv_f64 u0, mv_f64 v0, mv_f64 u1, mv_f64 v1, mv_f64 u2, mv_f64 v2, mv_f64 na) {
  if (na == 0.0) return true;
  mv_f64 s = na > 0.0 ? 1.0 : -1.0;
  return mv_thin_edge(u0, v0, u1, v1, s) && mv_thin_edge(u1, v1, u2, v2, s) && mv_thin_edge(u2, v2, u0, v0, s);
}

/* `column`: the projection mv_tri_thin_column already passed for the column along that axis is left out (3:
 * none; the same outcome, it reads only what the column's voxels share). */
MV_INLINE bool mv_tri_voxel_thin_in(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                    mv_f64 cy, mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k, mv_u32 grid, mv_u32 column) {
  const mv_f64 h = 0.5;
  MV_PRECISE mv_f64 v0x = ax - (MV_F64(i) + h), v0y = ay - (MV_F64(j) + h), v0z = az - (MV_F64(k) + h);
  MV_PRECISE mv_f64 v1x = bx - (MV_F64(i) + h), v1y = by - (MV_F64(j) + h), v1z = bz - (MV_F64(k) + h);
  MV_PRECISE mv_f64 v2x = cx - (MV_F64(i) + h), v2y = cy - (MV_F64(j) + h), v2z = cz - (MV_F64(k) + h);
  MV_PRECISE mv_f64 e0x = v1x - v0x, e0y = v1y - v0y, e0z = v1z - v0z;
  MV_PRECISE mv_f64 e1x = v2x - v1x, e1y = v2y - v1y, e1z = v2z - v1z;
  MV_PRECISE mv_f64 nx = e0y * e1z - e0z * e1y;
  MV_PRECISE mv_f64 ny = e0z * e1x - e0x * e1z;
  MV_PRECISE mv_f64 nz = e0x * e1y - e0y * e1x;
  mv_f64 ax_ = MV_FABS(nx), ay_ = MV_FABS(ny), az_ = MV_FABS(nz);
  mv_u32 d = (az_ >= ax_ && az_ >= ay_) ? 2u : (ay_ >= ax_) ? 1u : 0u;
  mv_f64 nd = d == 2u ? nz : d == 1u ? ny : nx;
  if (nd == 0.0) return false;
  bool top = (d == 2u ? k : d == 1u ? j : i) + 1u == grid; /* closed at the grid's top face */
  /* the plane crosses the centre line at c_d + w / n_d, w = n . (v0 - c); want w / n_d in [-1/2, 1/2) */
  MV_PRECISE mv_f64 w = nx * v0x + ny * v0y + nz * v0z;
  MV_PRECISE mv_f64 reach = h * MV_FABS(nd);
  bool below = nd > 0.0 ? w < -reach : w > reach;   /* crossing under c_d - 1/2 */
  bool above = nd > 0.0 ? w >= reach : w <= -reach; /* crossing at or over c_d + 1/2 */
  if (below || (above && !(top && w == (nd > 0.0 ? reach : -reach)))) return false;
  return (column == 0u || mv_thin_projection(v0y, v0z, v1y, v1z, v2y, v2z, nx)) &&
         (column == 1u || mv_thin_projection(v0z, v0x, v1z, v1x, v2z, v2x, ny)) &&
         (column == 2u || mv_thin_projection(v0x, v0y, v1x, v1y, v2x, v2y, nz));
}

MV_INLINE bool mv_tri_voxel_thin(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                 mv_f64 cy, mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k, mv_u32 grid) {
  return mv_tri_voxel_thin_in(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k, grid, 3u);
}

/* The projection test dropping axis d alone, for the column along d through voxel (i, j, k): it reads only
 * the two other coordinates, with the same operations as mv_tri_voxel_thin, so false means no voxel of the
 * column is set. */
MV_INLINE bool mv_tri_thin_column(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                  mv_f64 cy, mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k, mv_u32 d) {
  const mv_f64 h = 0.5;
  /* the cyclic pair (p, q) after d: x -> (y, z), y -> (z, x), z -> (x, y) */
  mv_f64 ap = d == 0u ? ay : d == 1u ? az : ax, aq = d == 0u ? az : d == 1u ? ax : ay;
  mv_f64 bp = d == 0u ? by : d == 1u ? bz : bx, bq = d == 0u ? bz : d == 1u ? bx : by;
  mv_f64 cp = d == 0u ? cy : d == 1u ? cz : cx, cq = d == 0u ? cz : d == 1u ? cx : cy;
  mv_u32 ip = d == 0u ? j : d == 1u ? k : i, iq = d == 0u ? k : d == 1u ? i : j;
  MV_PRECISE mv_f64 v0p = ap - (MV_F64(ip) + h), v0q = aq - (MV_F64(iq) + h);
  MV_PRECISE mv_f64 v1p = bp - (MV_F64(ip) + h), v1q = bq - (MV_F64(iq) + h);
  MV_PRECISE mv_f64 v2p = cp - (MV_F64(ip) + h), v2q = cq - (MV_F64(iq) + h);
  MV_PRECISE mv_f64 e0p = v1p - v0p, e0q = v1q - v0q;
  MV_PRECISE mv_f64 e1p = v2p - v1p, e1q = v2q - v1q;
  MV_PRECISE mv_f64 nd = e0p * e1q - e0q * e1p;
  return mv_thin_projection(v0p, v0q, v1p, v1q, v2p, v2q, nd);
}

#endif
