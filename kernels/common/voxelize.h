/* Surface voxelization of triangles into 64-bit Morton keys (3 x 21 bits, x lowest).
 *
 * Two rules: conservative (default; exact overlap, tri_box.h) or thin (6-separating, tri_thin.h).
 * Triangles arrive in grid units (9 floats each; the host maps world to grid). A voxel (i, j, k) is set when
 * the triangle meets its cell: exact separating-axis test (tri_box.h), half-open along the grid axes
 * ([i, i+1): a triangle lying in the plane x = i belongs to voxel i, not i-1) except that the top face of the
 * grid belongs to the last voxel; contact along an edge or a corner of a tilted triangle counts.
 *
 * Work is surface-proportional: each triangle walks the columns of its bounding box along its dominant
 * normal axis and tests only the few voxels of each column its plane can reach. A work item is a triangle
 * and a run of at most `columns_per_item` of its columns, so no loop grows with the triangle's size (GPUs
 * stay balanced; lavapipe's loop cap holds). Two passes with the same walk: count, then emit at the scanned
 * offsets. */
#ifndef MV_VOXELIZE_H
#define MV_VOXELIZE_H
#include "morton.h"
#include "tri_box.h"
#include "tri_thin.h"

MV_STRUCT_BEGIN(MvVoxelizeParams)
  mv_u32 first_item;       /* this dispatch covers items [first_item, first_item + items) */
  mv_u32 items;
  mv_u32 grid;             /* voxels per axis, N <= 2^21 */
  mv_u32 columns_per_item; /* columns one work item walks at most */
  mv_u32 emit;             /* 0: counts[item] = its voxels; 1: write their keys from keys[counts[item]] on */
  mv_u32 box_size;         /* only voxels of the cube [box, box + box_size) (out-of-core builds) */
  mv_u32 box_x;
  mv_u32 box_y;
  mv_u32 box_z;
  mv_u32 thin;             /* 0: conservative (tri_box.h); 1: thin, 6-separating (tri_thin.h) */
MV_STRUCT_END(MvVoxelizeParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvVoxelizeParams, 40);
MV_LAYOUT_AT(MvVoxelizeParams, first_item, 0); MV_LAYOUT_AT(MvVoxelizeParams, items, 4);
MV_LAYOUT_AT(MvVoxelizeParams, grid, 8); MV_LAYOUT_AT(MvVoxelizeParams, columns_per_item, 12);
MV_LAYOUT_AT(MvVoxelizeParams, emit, 16); MV_LAYOUT_AT(MvVoxelizeParams, box_size, 20);
MV_LAYOUT_AT(MvVoxelizeParams, box_x, 24); MV_LAYOUT_AT(MvVoxelizeParams, box_y, 28);
MV_LAYOUT_AT(MvVoxelizeParams, box_z, 32); MV_LAYOUT_AT(MvVoxelizeParams, thin, 36);
#endif

/* Where a triangle's walk goes: the dominant axis d (0 = x, 1 = y, 2 = z; ties go to the later axis) with
 * the two others u < v, and the voxel range of its bounding box, clamped to the grid and to the box
 * (empty = 1 when they do not meet). */
MV_STRUCT_BEGIN(MvTriFrame)
  mv_u32 d;
  mv_u32 u;
  mv_u32 v;
  mv_u32 lo0;
  mv_u32 lo1;
  mv_u32 lo2;
  mv_u32 hi0;
  mv_u32 hi1;
  mv_u32 hi2;
  mv_u32 empty;
MV_STRUCT_END(MvTriFrame)

MV_INLINE mv_u32 mv_voxel_floor(mv_f64 x, mv_u32 grid) {
  if (x <= 0.0) return 0u;
  mv_f64 f = floor(x);
  return f >= MV_F64(grid) ? grid - 1u : MV_U32(f);
}

MV_INLINE MvTriFrame mv_tri_frame(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                  mv_f64 cy, mv_f64 cz, mv_u32 grid, mv_u32 box_x, mv_u32 box_y, mv_u32 box_z,
                                  mv_u32 box_size) {
  MvTriFrame f;
  MV_PRECISE mv_f64 e0x = bx - ax, e0y = by - ay, e0z = bz - az;
  MV_PRECISE mv_f64 e1x = cx - bx, e1y = cy - by, e1z = cz - bz;
  MV_PRECISE mv_f64 nx = MV_FABS(e0y * e1z - e0z * e1y);
  MV_PRECISE mv_f64 ny = MV_FABS(e0z * e1x - e0x * e1z);
  MV_PRECISE mv_f64 nz = MV_FABS(e0x * e1y - e0y * e1x);
  if (nz >= nx && nz >= ny) {
    f.d = 2u; f.u = 0u; f.v = 1u;
  } else if (ny >= nx) {
    f.d = 1u; f.u = 0u; f.v = 2u;
  } else {
    f.d = 0u; f.u = 1u; f.v = 2u;
  }
  f.lo0 = mv_voxel_floor(MV_FMIN(ax, MV_FMIN(bx, cx)), grid);
  f.lo1 = mv_voxel_floor(MV_FMIN(ay, MV_FMIN(by, cy)), grid);
  f.lo2 = mv_voxel_floor(MV_FMIN(az, MV_FMIN(bz, cz)), grid);
  f.hi0 = mv_voxel_floor(MV_FMAX(ax, MV_FMAX(bx, cx)), grid);
  f.hi1 = mv_voxel_floor(MV_FMAX(ay, MV_FMAX(by, cy)), grid);
  f.hi2 = mv_voxel_floor(MV_FMAX(az, MV_FMAX(bz, cz)), grid);
  f.lo0 = MV_MAX(f.lo0, box_x);
  f.lo1 = MV_MAX(f.lo1, box_y);
  f.lo2 = MV_MAX(f.lo2, box_z);
  f.hi0 = MV_MIN(f.hi0, box_x + box_size - 1u);
  f.hi1 = MV_MIN(f.hi1, box_y + box_size - 1u);
  f.hi2 = MV_MIN(f.hi2, box_z + box_size - 1u);
  f.empty = (f.lo0 > f.hi0 || f.lo1 > f.hi1 || f.lo2 > f.hi2) ? 1u : 0u;
  return f;
}

MV_INLINE mv_u32 mv_frame_lo(MvTriFrame f, mv_u32 axis) { return axis == 0u ? f.lo0 : axis == 1u ? f.lo1 : f.lo2; }
MV_INLINE mv_u32 mv_frame_hi(MvTriFrame f, mv_u32 axis) { return axis == 0u ? f.hi0 : axis == 1u ? f.hi1 : f.hi2; }

/* Columns a triangle's walk visits: the voxels of its bounding box projected along the dominant axis. */
MV_INLINE mv_u32 mv_frame_columns(MvTriFrame f) {
  if (f.empty != 0u) return 0u;
  return (mv_frame_hi(f, f.u) - mv_frame_lo(f, f.u) + 1u) * (mv_frame_hi(f, f.v) - mv_frame_lo(f, f.v) + 1u);
}

MV_INLINE mv_f64 mv_pick(mv_f64 x, mv_f64 y, mv_f64 z, mv_u32 axis) { return axis == 0u ? x : axis == 1u ? y : z; }

/* Half-open along the grid axes (see the top of this file): the closed test, minus cells the triangle only
 * touches from above (all of it at or beyond the cell's upper face, except on the grid's top face). The
 * thin rule keeps the same exclusion, so thin voxels stay within the conservative ones. */
MV_INLINE bool mv_voxel_hit(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx, mv_f64 cy,
                            mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k, mv_u32 grid, mv_u32 thin) {
  if (i + 1u < grid && MV_FMIN(ax, MV_FMIN(bx, cx)) >= MV_F64(i + 1u)) return false;
  if (j + 1u < grid && MV_FMIN(ay, MV_FMIN(by, cy)) >= MV_F64(j + 1u)) return false;
  if (k + 1u < grid && MV_FMIN(az, MV_FMIN(bz, cz)) >= MV_F64(k + 1u)) return false;
  if (thin != 0u) return mv_tri_voxel_thin(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k, grid);
  return mv_tri_box_overlap(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k);
}

/* One work item: columns [first, first + columns_per_item) of triangle t's walk. Returns the voxel count;
 * with p.emit writes their keys from keys[at] on. */
MV_INLINE mv_u32 mv_voxelize_item(MvBufF32 tris, MvBufU64 keys, mv_u32 at, mv_u32 t, mv_u32 first,
                                  MvVoxelizeParams p) {
  mv_f64 ax = MV_F64(MV_LD(tris, 9u * t + 0u)), ay = MV_F64(MV_LD(tris, 9u * t + 1u)), az = MV_F64(MV_LD(tris, 9u * t + 2u));
  mv_f64 bx = MV_F64(MV_LD(tris, 9u * t + 3u)), by = MV_F64(MV_LD(tris, 9u * t + 4u)), bz = MV_F64(MV_LD(tris, 9u * t + 5u));
  mv_f64 cx = MV_F64(MV_LD(tris, 9u * t + 6u)), cy = MV_F64(MV_LD(tris, 9u * t + 7u)), cz = MV_F64(MV_LD(tris, 9u * t + 8u));
  MvTriFrame f = mv_tri_frame(ax, ay, az, bx, by, bz, cx, cy, cz, p.grid, p.box_x, p.box_y, p.box_z, p.box_size);
  mv_u32 ulo = mv_frame_lo(f, f.u), vlo = mv_frame_lo(f, f.v), dlo = mv_frame_lo(f, f.d), dhi = mv_frame_hi(f, f.d);
  mv_u32 width = mv_frame_hi(f, f.u) - ulo + 1u;
  mv_u32 last = MV_MIN(first + p.columns_per_item, mv_frame_columns(f));
  /* plane n . x = w, to bound the dominant coordinate over a column */
  MV_PRECISE mv_f64 e0x = bx - ax, e0y = by - ay, e0z = bz - az;
  MV_PRECISE mv_f64 e1x = cx - bx, e1y = cy - by, e1z = cz - bz;
  MV_PRECISE mv_f64 nx = e0y * e1z - e0z * e1y;
  MV_PRECISE mv_f64 ny = e0z * e1x - e0x * e1z;
  MV_PRECISE mv_f64 nz = e0x * e1y - e0y * e1x;
  MV_PRECISE mv_f64 w = nx * ax + ny * ay + nz * az;
  mv_f64 nd = mv_pick(nx, ny, nz, f.d), nu = mv_pick(nx, ny, nz, f.u), nv = mv_pick(nx, ny, nz, f.v);
  mv_u32 found = 0u;
  for (mv_u32 col = first; col < last; ++col) {
    mv_u32 cu = ulo + col % width, cv = vlo + col / width;
    mv_u32 d0 = dlo, d1 = dhi;
    if (nd != 0.0) { /* the plane's reach over the closed column square, one voxel of slack each side */
      MV_PRECISE mv_f64 s00 = (w - nu * MV_F64(cu) - nv * MV_F64(cv)) / nd;
      MV_PRECISE mv_f64 s10 = (w - nu * MV_F64(cu + 1u) - nv * MV_F64(cv)) / nd;
      MV_PRECISE mv_f64 s01 = (w - nu * MV_F64(cu) - nv * MV_F64(cv + 1u)) / nd;
      MV_PRECISE mv_f64 s11 = (w - nu * MV_F64(cu + 1u) - nv * MV_F64(cv + 1u)) / nd;
      mv_f64 smin = MV_FMIN(MV_FMIN(s00, s10), MV_FMIN(s01, s11)) - 1.0;
      mv_f64 smax = MV_FMAX(MV_FMAX(s00, s10), MV_FMAX(s01, s11)) + 1.0;
      d0 = MV_MAX(d0, mv_voxel_floor(smin, p.grid));
      d1 = MV_MIN(d1, mv_voxel_floor(smax, p.grid));
    }
    for (mv_u32 cd = d0; cd <= d1; ++cd) {
      mv_u32 x = f.d == 0u ? cd : cu;
      mv_u32 y = f.d == 1u ? cd : f.d == 0u ? cu : cv;
      mv_u32 z = f.d == 2u ? cd : cv;
      if (mv_voxel_hit(ax, ay, az, bx, by, bz, cx, cy, cz, x, y, z, p.grid, p.thin)) {
        if (p.emit != 0u) MV_ST(keys, at + found, mv_morton3_64(x, y, z));
        found += 1u;
      }
    }
  }
  return found;
}

#endif
