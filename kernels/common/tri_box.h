/* Exact, conservative triangle / voxel overlap: the separating-axis test of Akenine-Moeller (2001) against
 * the closed voxel [i, i+1] x [j, j+1] x [k, k+1], so a triangle touching a face or edge marks the voxel.
 * Decisive, so it is written once for every language and evaluated in double with a fixed order and no
 * contraction (OpenCL FP_CONTRACT OFF, GLSL `precise`, host -ffp-contract=off): PoCL, lavapipe, GPUs and the
 * CPU reference give the same voxels. Vertices are in grid units (floats); subtracting the voxel centre
 * (a half-integer) from a float is exact in double. The order of the axes changes speed, not the result. */
#ifndef MV_TRI_BOX_H
#define MV_TRI_BOX_H
#include "mv_lang.h"

/* Does the projection of the triangle on `axis` miss the box's projection [-r, r]? */
MV_INLINE bool mv_axis_separates(mv_f64 p0, mv_f64 p1, mv_f64 p2, mv_f64 r) {
  MV_PRECISE mv_f64 lo = MV_FMIN(p0, MV_FMIN(p1, p2));
  MV_PRECISE mv_f64 hi = MV_FMAX(p0, MV_FMAX(p1, p2));
  return lo > r || hi < -r;
}

/* Does the projection of the triangle on the axis p (the cross product of a box axis with an edge) miss the
 * box's? Vertices relative to the voxel centre. */
MV_ALWAYS_INLINE bool mv_edge_axis_separates(mv_f64 v0x, mv_f64 v0y, mv_f64 v0z, mv_f64 v1x, mv_f64 v1y, mv_f64 v1z,
                                      mv_f64 v2x, mv_f64 v2y, mv_f64 v2z, mv_f64 px, mv_f64 py, mv_f64 pz) {
  const mv_f64 h = 0.5;
  MV_PRECISE mv_f64 q0 = v0x * px + v0y * py + v0z * pz;
  MV_PRECISE mv_f64 q1 = v1x * px + v1y * py + v1z * pz;
  MV_PRECISE mv_f64 q2 = v2x * px + v2y * py + v2z * pz;
  MV_PRECISE mv_f64 rr = h * MV_FABS(px) + h * MV_FABS(py) + h * MV_FABS(pz);
  return mv_axis_separates(q0, q1, q2, rr);
}

/* The three edge axes of box axis a: x cross e = (0, -ez, ey), y cross e = (ez, 0, -ex), z cross e = (-ey, ex,
 * 0). They read only the vertices' two other coordinates (the a-th is multiplied by an exact 0), so a column
 * walk along a runs them once per column (mv_tri_box_column) with the same outcome as per voxel. One
 * straight-line function per axis, always inlined: as a called function, a loop over axes and edges with selects takes
 * half of the voxelizer's time on PoCL. */
#if defined(MV_CPP) && defined(__GNUC__) /* each axis reads six of the nine edge components it names */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-variable"
#endif
#define MV_EDGE_AXES(name, X0, Y0, Z0, X1, Y1, Z1, X2, Y2, Z2)                                                         \
  MV_ALWAYS_INLINE bool name(mv_f64 v0x, mv_f64 v0y, mv_f64 v0z, mv_f64 v1x, mv_f64 v1y, mv_f64 v1z, mv_f64 v2x, mv_f64 v2y,  \
                      mv_f64 v2z) {                                                                                    \
    MV_PRECISE mv_f64 e0x = v1x - v0x, e0y = v1y - v0y, e0z = v1z - v0z;                                               \
    MV_PRECISE mv_f64 e1x = v2x - v1x, e1y = v2y - v1y, e1z = v2z - v1z;                                               \
    MV_PRECISE mv_f64 e2x = v0x - v2x, e2y = v0y - v2y, e2z = v0z - v2z;                                               \
    return mv_edge_axis_separates(v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z, X0, Y0, Z0) ||                         \
           mv_edge_axis_separates(v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z, X1, Y1, Z1) ||                         \
           mv_edge_axis_separates(v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z, X2, Y2, Z2);                           \
  }
MV_EDGE_AXES(mv_edge_axes_x_separate, 0.0, -e0z, e0y, 0.0, -e1z, e1y, 0.0, -e2z, e2y)
MV_EDGE_AXES(mv_edge_axes_y_separate, e0z, 0.0, -e0x, e1z, 0.0, -e1x, e2z, 0.0, -e2x)
MV_EDGE_AXES(mv_edge_axes_z_separate, -e0y, e0x, 0.0, -e1y, e1x, 0.0, -e2y, e2x, 0.0)
#undef MV_EDGE_AXES
#if defined(MV_CPP) && defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

/* Triangle (a, b, c) in grid units against voxel (i, j, k), leaving out the tests mv_tri_box_column already
 * passed for the column along axis `column` through the voxel (3: none left out; the outcome is the same,
 * since those tests read only what the column's voxels share). */
MV_INLINE bool mv_tri_box_overlap_in(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                     mv_f64 cy, mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k, mv_u32 column) {
  const mv_f64 h = 0.5;
  /* vertices relative to the voxel centre */
  MV_PRECISE mv_f64 v0x = ax - (MV_F64(i) + h), v0y = ay - (MV_F64(j) + h), v0z = az - (MV_F64(k) + h);
  MV_PRECISE mv_f64 v1x = bx - (MV_F64(i) + h), v1y = by - (MV_F64(j) + h), v1z = bz - (MV_F64(k) + h);
  MV_PRECISE mv_f64 v2x = cx - (MV_F64(i) + h), v2y = cy - (MV_F64(j) + h), v2z = cz - (MV_F64(k) + h);
  /* 1. the box's own axes: the triangle's bounding box */
  if ((column == 0u || column == 3u) && mv_axis_separates(v0x, v1x, v2x, h)) return false;
  if ((column == 1u || column == 3u) && mv_axis_separates(v0y, v1y, v2y, h)) return false;
  if ((column == 2u || column == 3u) && mv_axis_separates(v0z, v1z, v2z, h)) return false;
  MV_PRECISE mv_f64 e0x = v1x - v0x, e0y = v1y - v0y, e0z = v1z - v0z;
  MV_PRECISE mv_f64 e1x = v2x - v1x, e1y = v2y - v1y, e1z = v2z - v1z;
  /* 2. the triangle's normal: cheap, and it rejects most candidates of a column walk */
  {
    MV_PRECISE mv_f64 nx = e0y * e1z - e0z * e1y;
    MV_PRECISE mv_f64 ny = e0z * e1x - e0x * e1z;
    MV_PRECISE mv_f64 nz = e0x * e1y - e0y * e1x;
    MV_PRECISE mv_f64 d = nx * v0x + ny * v0y + nz * v0z;
    MV_PRECISE mv_f64 rr = h * MV_FABS(nx) + h * MV_FABS(ny) + h * MV_FABS(nz);
    if (d > rr || d < -rr) return false;
  }
  /* 3. the nine cross products of the box axes with the edges */
  return (column == 0u || !mv_edge_axes_x_separate(v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z)) &&
         (column == 1u || !mv_edge_axes_y_separate(v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z)) &&
         (column == 2u || !mv_edge_axes_z_separate(v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z));
}

/* Triangle (a, b, c) in grid units against voxel (i, j, k): every test. */
MV_INLINE bool mv_tri_box_overlap(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                  mv_f64 cy, mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k) {
  return mv_tri_box_overlap_in(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k, 3u);
}

/* The part of mv_tri_box_overlap that depends only on a column along axis d through voxel (i, j, k) (its
 * d-th coordinate is ignored): the box's two other axes and the three edge axes of box axis d. False: no
 * voxel of the column overlaps. */
MV_INLINE bool mv_tri_box_column(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                 mv_f64 cy, mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k, mv_u32 d) {
  const mv_f64 h = 0.5;
  /* the d-th coordinates only meet an exact 0 in these tests: any finite value gives the same outcome */
  MV_PRECISE mv_f64 v0x = d == 0u ? 0.0 : ax - (MV_F64(i) + h), v0y = d == 1u ? 0.0 : ay - (MV_F64(j) + h);
  MV_PRECISE mv_f64 v0z = d == 2u ? 0.0 : az - (MV_F64(k) + h);
  MV_PRECISE mv_f64 v1x = d == 0u ? 0.0 : bx - (MV_F64(i) + h), v1y = d == 1u ? 0.0 : by - (MV_F64(j) + h);
  MV_PRECISE mv_f64 v1z = d == 2u ? 0.0 : bz - (MV_F64(k) + h);
  MV_PRECISE mv_f64 v2x = d == 0u ? 0.0 : cx - (MV_F64(i) + h), v2y = d == 1u ? 0.0 : cy - (MV_F64(j) + h);
  MV_PRECISE mv_f64 v2z = d == 2u ? 0.0 : cz - (MV_F64(k) + h);
  if ((d != 0u && mv_axis_separates(v0x, v1x, v2x, h)) || (d != 1u && mv_axis_separates(v0y, v1y, v2y, h)) ||
      (d != 2u && mv_axis_separates(v0z, v1z, v2z, h)))
    return false;
  if (d == 0u) return !mv_edge_axes_x_separate(v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z);
  if (d == 1u) return !mv_edge_axes_y_separate(v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z);
  return !mv_edge_axes_z_separate(v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z);
}

#endif
