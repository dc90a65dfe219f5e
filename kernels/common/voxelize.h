/* Surface voxelization of triangles into 4^3 bricks: per non-empty brick its 64-bit Morton key (3 x 21 bits of
 * the brick coordinates, x lowest; = the voxel key >> 6) and its occupancy as one 64-bit mask (bit i = the
 * voxel whose Morton index inside the brick is i), the bottom of the octree as the DAG build takes it.
 *
 * Two rules: conservative (default; exact overlap, tri_box.h) or thin (6-separating, tri_thin.h).
 * Triangles arrive in grid units (9 floats each; the host maps world to grid). A voxel (i, j, k) is set when
 * the triangle meets its cell: exact separating-axis test (tri_box.h), half-open along the grid axes
 * ([i, i+1): a triangle lying in the plane x = i belongs to voxel i, not i-1) except that the top face of the
 * grid belongs to the last voxel; contact along an edge or a corner of a tilted triangle counts.
 *
 * Work grows with the surface: each triangle walks the brick columns of its bounding box along its dominant
 * normal axis d; in each, the 16 voxel columns are pruned by the predicate's own column-only tests
 * (mv_tri_box_column / mv_tri_thin_column: the same operations, so nothing the per-voxel test keeps is
 * dropped), then only the cells of a column the plane can reach (its exact reach plus a rounding bound) get
 * the per-voxel predicate, whose bits fill one mask per brick layer. A work item is a triangle and a run of
 * at most `columns_per_item` brick columns, so no loop grows with the triangle's size (GPUs stay balanced;
 * lavapipe's loop cap holds). One pass: each non-empty brick takes the next slot of an atomic counter, so
 * the order of the output varies from run to run, and a brick met by several triangles comes out once per
 * triangle: the host sorts by key and ORs repeats, which gives the same bytes every time. A count past the
 * capacity tells the host to run those items again with more room. With `record_tris`, each slot also gets
 * its triangle's index: these (brick, mask, triangle) fragments are what mesh colours take (mesh_colour.h). */
#ifndef MV_VOXELIZE_H
#define MV_VOXELIZE_H
#include "morton.h"
#include "tri_box.h"
#include "tri_thin.h"

MV_STRUCT_BEGIN(MvVoxelizeParams)
  mv_u32 first_item;       /* this dispatch covers items [first_item, first_item + items) */
  mv_u32 items;
  mv_u32 grid;             /* voxels per axis, N <= 2^21 */
  mv_u32 columns_per_item; /* brick columns one work item walks at most */
  mv_u32 capacity;         /* bricks the keys and masks buffers hold; past it, bricks are counted, not written
                              (mesh colours: the voxels) */
  mv_u32 box_size;         /* only voxels of the cube [box, box + box_size) (out-of-core builds) */
  mv_u32 box_x;
  mv_u32 box_y;
  mv_u32 box_z;
  mv_u32 thin;             /* 0: conservative (tri_box.h); 1: thin, 6-separating (tri_thin.h) */
  mv_u32 colour_pass;      /* mesh colours (mesh_colour.h): the pass, 1 to 3 */
  mv_u32 bricks;           /* mesh colours: the bricks of the voxel set */
  mv_u32 tri_base;         /* the index of this batch's first triangle (recorded, or mesh colours') */
  mv_u32 record_tris;      /* voxelizing: 1 writes each slot's triangle index (tri_base + its place) */
  mv_u32 batch_tris;       /* mesh colours: the triangles of this batch */
  mv_u32 split_runs;       /* mesh colours: 1 when a brick's fragments may span batches of triangles */
MV_STRUCT_END(MvVoxelizeParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvVoxelizeParams, 64);
MV_LAYOUT_AT(MvVoxelizeParams, first_item, 0); MV_LAYOUT_AT(MvVoxelizeParams, items, 4);
MV_LAYOUT_AT(MvVoxelizeParams, grid, 8); MV_LAYOUT_AT(MvVoxelizeParams, columns_per_item, 12);
MV_LAYOUT_AT(MvVoxelizeParams, capacity, 16); MV_LAYOUT_AT(MvVoxelizeParams, box_size, 20);
MV_LAYOUT_AT(MvVoxelizeParams, box_x, 24); MV_LAYOUT_AT(MvVoxelizeParams, box_y, 28);
MV_LAYOUT_AT(MvVoxelizeParams, box_z, 32); MV_LAYOUT_AT(MvVoxelizeParams, thin, 36);
MV_LAYOUT_AT(MvVoxelizeParams, colour_pass, 40); MV_LAYOUT_AT(MvVoxelizeParams, bricks, 44);
MV_LAYOUT_AT(MvVoxelizeParams, tri_base, 48); MV_LAYOUT_AT(MvVoxelizeParams, record_tris, 52);
MV_LAYOUT_AT(MvVoxelizeParams, batch_tris, 56); MV_LAYOUT_AT(MvVoxelizeParams, split_runs, 60);
#endif
#include "mesh_colour.h"

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

/* The cell holding x, clamped to the grid: floor by truncation, x being positive (no floor(double) call). */
MV_INLINE mv_u32 mv_voxel_floor(mv_f64 x, mv_u32 grid) {
  if (x <= 0.0) return 0u;
  return x >= MV_F64(grid) ? grid - 1u : MV_U32(x);
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

/* Brick columns a triangle's walk visits: the 4 x 4 voxel columns of its bounding box projected along the
 * dominant axis. */
MV_INLINE mv_u32 mv_frame_columns(MvTriFrame f) {
  if (f.empty != 0u) return 0u;
  return ((mv_frame_hi(f, f.u) >> 2) - (mv_frame_lo(f, f.u) >> 2) + 1u) *
         ((mv_frame_hi(f, f.v) >> 2) - (mv_frame_lo(f, f.v) >> 2) + 1u);
}

/* Bit of voxel (x, y, z) in its brick's mask: its Morton index inside the brick. */
MV_INLINE mv_u32 mv_brick_bit(mv_u32 x, mv_u32 y, mv_u32 z) {
  return (x & 1u) | ((y & 1u) << 1) | ((z & 1u) << 2) | ((x & 2u) << 2) | ((y & 2u) << 3) | ((z & 2u) << 4);
}

/* Column-only parts of the predicate (see mv_voxel_hit): false when no voxel of the column along d through
 * (i, j, k) can be set. */
MV_INLINE bool mv_column_may_hit(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                 mv_f64 cy, mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k, mv_u32 d, mv_u32 thin) {
  if (thin != 0u) return mv_tri_thin_column(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k, d);
  return mv_tri_box_column(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k, d);
}

MV_INLINE mv_f64 mv_pick(mv_f64 x, mv_f64 y, mv_f64 z, mv_u32 axis) { return axis == 0u ? x : axis == 1u ? y : z; }

/* Half-open along the grid axes (see the top of this file): the closed test, minus cells the triangle only
 * touches from above (all of it at or beyond the cell's upper face, except on the grid's top face). The
 * thin rule keeps the same exclusion, so thin voxels stay within the conservative ones. */
/* `column`: a voxel of a column along that axis whose column tests passed (mv_column_may_hit), whose tests
 * are then left out; 3 = every test. */
MV_INLINE bool mv_voxel_hit_in(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx, mv_f64 cy,
                               mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k, mv_u32 grid, mv_u32 thin, mv_u32 column) {
  if (i + 1u < grid && MV_FMIN(ax, MV_FMIN(bx, cx)) >= MV_F64(i + 1u)) return false;
  if (j + 1u < grid && MV_FMIN(ay, MV_FMIN(by, cy)) >= MV_F64(j + 1u)) return false;
  if (k + 1u < grid && MV_FMIN(az, MV_FMIN(bz, cz)) >= MV_F64(k + 1u)) return false;
  if (thin != 0u) return mv_tri_voxel_thin_in(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k, grid, column);
  return mv_tri_box_overlap_in(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k, column);
}

MV_INLINE bool mv_voxel_hit(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx, mv_f64 cy,
                            mv_f64 cz, mv_u32 i, mv_u32 j, mv_u32 k, mv_u32 grid, mv_u32 thin) {
  return mv_voxel_hit_in(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k, grid, thin, 3u);
}

/* A triangle's plane n . x = w over its walk: the reach of the dominant coordinate over a column. */
MV_STRUCT_BEGIN(MvTriPlane)
  mv_f64 w;
  mv_f64 nd;
  mv_f64 nu;
  mv_f64 nv;
  mv_f64 slack;
  mv_u32 centre; /* thin rule, and the predicate surely picks axis d: test only the cells at the centre line */
MV_STRUCT_END(MvTriPlane)

MV_INLINE MvTriPlane mv_tri_plane(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                  mv_f64 cy, mv_f64 cz, MvTriFrame f, mv_u32 grid, mv_u32 thin) {
  MvTriPlane pl;
  MV_PRECISE mv_f64 e0x = bx - ax, e0y = by - ay, e0z = bz - az;
  MV_PRECISE mv_f64 e1x = cx - bx, e1y = cy - by, e1z = cz - bz;
  MV_PRECISE mv_f64 nx = e0y * e1z - e0z * e1y;
  MV_PRECISE mv_f64 ny = e0z * e1x - e0x * e1z;
  MV_PRECISE mv_f64 nz = e0x * e1y - e0y * e1x;
  MV_PRECISE mv_f64 w = nx * ax + ny * ay + nz * az;
  pl.w = w;
  pl.nd = mv_pick(nx, ny, nz, f.d);
  pl.nu = mv_pick(nx, ny, nz, f.u);
  pl.nv = mv_pick(nx, ny, nz, f.v);
  /* How far the reach computed here may sit from the plane the predicate sees (its normal is rounded from
   * other differences): a bound on both normals' rounding over the triangle's extent, as a slope error times
   * that extent, plus the rounding of w and of the reach itself; generous, it costs only a few more tests. */
  pl.slack = 0.0;
  if (pl.nd != 0.0) {
    mv_f64 l0 = MV_FABS(e0x) + MV_FABS(e0y) + MV_FABS(e0z), l1 = MV_FABS(e1x) + MV_FABS(e1y) + MV_FABS(e1z);
    mv_f64 extent = l0 + l1 + 2.0;
    pl.slack = 1.0 / 1024.0 + MV_F64(grid) / 1099511627776.0 /* 2^-40 */ +
               l0 * l1 * extent / MV_FABS(pl.nd) / 70368744177664.0 /* 2^-46 */;
  }
  /* The thin predicate sets in a column only the cell where the plane crosses the column's centre line along
   * ITS dominant axis (tri_thin.h). When ours is d by more than both normals' rounding (a bound like the
   * slack's: 2^-44 (l0 + l1 + 2)^2 per component), that axis is d too, and only the cells around the crossing
   * at the centre, within the slack, are candidates: about one a column instead of the plane's whole reach. */
  pl.centre = 0u;
  if (thin != 0u && pl.nd != 0.0) {
    mv_f64 l = MV_FABS(e0x) + MV_FABS(e0y) + MV_FABS(e0z) + MV_FABS(e1x) + MV_FABS(e1y) + MV_FABS(e1z) + 2.0;
    mv_f64 delta = l * l / 17592186044416.0; /* 2^-44 */
    if (MV_FABS(pl.nd) > MV_FMAX(MV_FABS(pl.nu), MV_FABS(pl.nv)) + 2.0 * delta) pl.centre = 1u;
  }
  return pl;
}

/* Brick columns [first, last) of a walk along axis d (a constant at each call, so the compiler specializes
 * the walk and hoists what a column's cells share; the predicate's operations stay the same). */
MV_INLINE void mv_voxelize_columns(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz, mv_f64 cx,
                                     mv_f64 cy, mv_f64 cz, MvTriFrame f, MvTriPlane pl, mv_u32 d, mv_u32 first,
                                     mv_u32 last, MvBufU32 counter, MvBufU64 keys, MvBufU64 masks,
                                     MvBufU32 slot_tris, MvVoxelizeParams p, mv_u32 tri) {
  mv_u32 u = d == 0u ? 1u : 0u, v = d == 2u ? 1u : 2u;
  mv_u32 ulo = mv_frame_lo(f, u), uhi = mv_frame_hi(f, u), vlo = mv_frame_lo(f, v), vhi = mv_frame_hi(f, v);
  mv_u32 dlo = mv_frame_lo(f, d), dhi = mv_frame_hi(f, d);
  mv_u32 width = (uhi >> 2) - (ulo >> 2) + 1u;
  for (mv_u32 col = first; col < last; ++col) {
    mv_u32 bu = (ulo >> 2) + col % width, bv = (vlo >> 2) + col / width;
    /* the 16 voxel columns: the cells [r0, r1] along d each may set (empty when r0 > r1) */
    mv_u32 r0[16];
    mv_u32 r1[16];
    mv_u32 lmin = 0xffffffffu, lmax = 0u;
    for (mv_u32 q = 0u; q < 16u; ++q) {
      mv_u32 cu = 4u * bu + (q & 3u), cv = 4u * bv + (q >> 2);
      r0[q] = 1u;
      r1[q] = 0u;
      if (cu < ulo || cu > uhi || cv < vlo || cv > vhi) continue;
      mv_u32 i = d == 0u ? 0u : cu;
      mv_u32 j = d == 1u ? 0u : d == 0u ? cu : cv;
      mv_u32 k = d == 2u ? 0u : cv;
      if (!mv_column_may_hit(ax, ay, az, bx, by, bz, cx, cy, cz, i, j, k, d, p.thin)) continue;
      mv_u32 d0 = dlo, d1 = dhi;
      if (pl.nd != 0.0) {
        mv_f64 smin, smax;
        if (pl.centre != 0u) { /* the crossing at the column's centre line */
          MV_PRECISE mv_f64 sc = (pl.w - pl.nu * (MV_F64(cu) + 0.5) - pl.nv * (MV_F64(cv) + 0.5)) / pl.nd;
          smin = sc - pl.slack;
          smax = sc + pl.slack;
        } else { /* the plane's reach over the closed column square */
          MV_PRECISE mv_f64 s00 = (pl.w - pl.nu * MV_F64(cu) - pl.nv * MV_F64(cv)) / pl.nd;
          MV_PRECISE mv_f64 s10 = (pl.w - pl.nu * MV_F64(cu + 1u) - pl.nv * MV_F64(cv)) / pl.nd;
          MV_PRECISE mv_f64 s01 = (pl.w - pl.nu * MV_F64(cu) - pl.nv * MV_F64(cv + 1u)) / pl.nd;
          MV_PRECISE mv_f64 s11 = (pl.w - pl.nu * MV_F64(cu + 1u) - pl.nv * MV_F64(cv + 1u)) / pl.nd;
          smin = MV_FMIN(MV_FMIN(s00, s10), MV_FMIN(s01, s11)) - pl.slack;
          smax = MV_FMAX(MV_FMAX(s00, s10), MV_FMAX(s01, s11)) + pl.slack;
        }
        if (smax < MV_F64(dlo) || smin > MV_F64(dhi + 1u)) continue;
        d0 = MV_MAX(d0, mv_voxel_floor(smin, p.grid));
        d1 = MV_MIN(d1, mv_voxel_floor(smax, p.grid));
      }
      r0[q] = d0;
      r1[q] = d1;
      lmin = MV_MIN(lmin, d0 >> 2);
      lmax = MV_MAX(lmax, d1 >> 2);
    }
    /* one brick per layer of the brick column: its mask from the cells of that layer */
    for (mv_u32 layer = lmin; layer <= lmax; ++layer) {
      mv_u64 mask = MV_U64(0u);
      for (mv_u32 q = 0u; q < 16u; ++q) {
        mv_u32 cu = 4u * bu + (q & 3u), cv = 4u * bv + (q >> 2);
        mv_u32 c0 = MV_MAX(r0[q], 4u * layer), c1 = MV_MIN(r1[q], 4u * layer + 3u);
        for (mv_u32 cd = c0; cd <= c1; ++cd) {
          mv_u32 x = d == 0u ? cd : cu;
          mv_u32 y = d == 1u ? cd : d == 0u ? cu : cv;
          mv_u32 z = d == 2u ? cd : cv;
          if (mv_voxel_hit_in(ax, ay, az, bx, by, bz, cx, cy, cz, x, y, z, p.grid, p.thin, d))
            mask |= MV_U64(1u) << mv_brick_bit(x, y, z);
        }
      }
      if (mask == MV_U64(0u)) continue;
      mv_u32 bx_ = d == 0u ? layer : bu;
      mv_u32 by_ = d == 1u ? layer : d == 0u ? bu : bv;
      mv_u32 bz_ = d == 2u ? layer : bv;
      mv_u32 slot = MV_ATOMIC_ADD(counter, 0u, 1u);
      if (slot >= p.capacity) continue;
      MV_ST(keys, slot, mv_morton3_64(bx_, by_, bz_));
      MV_ST(masks, slot, mask);
      if (p.record_tris != 0u) MV_ST(slot_tris, slot, tri);
    }
  }
}

/* One work item: brick columns [first, first + columns_per_item) of triangle t's walk; its non-empty bricks
 * go to the slots the counter hands out. */
MV_INLINE void mv_voxelize_item(MvBufF32 tris, MvBufU32 counter, MvBufU64 keys, MvBufU64 masks,
                                MvBufU32 slot_tris, mv_u32 t, mv_u32 first, MvVoxelizeParams p) {
  mv_f64 ax = MV_F64(MV_LD(tris, 9u * t + 0u)), ay = MV_F64(MV_LD(tris, 9u * t + 1u)), az = MV_F64(MV_LD(tris, 9u * t + 2u));
  mv_f64 bx = MV_F64(MV_LD(tris, 9u * t + 3u)), by = MV_F64(MV_LD(tris, 9u * t + 4u)), bz = MV_F64(MV_LD(tris, 9u * t + 5u));
  mv_f64 cx = MV_F64(MV_LD(tris, 9u * t + 6u)), cy = MV_F64(MV_LD(tris, 9u * t + 7u)), cz = MV_F64(MV_LD(tris, 9u * t + 8u));
  MvTriFrame f = mv_tri_frame(ax, ay, az, bx, by, bz, cx, cy, cz, p.grid, p.box_x, p.box_y, p.box_z, p.box_size);
  MvTriPlane pl = mv_tri_plane(ax, ay, az, bx, by, bz, cx, cy, cz, f, p.grid, p.thin);
  mv_u32 last = MV_MIN(first + p.columns_per_item, mv_frame_columns(f));
  mv_u32 tri = p.tri_base + t;
  if (f.d == 0u) mv_voxelize_columns(ax, ay, az, bx, by, bz, cx, cy, cz, f, pl, 0u, first, last, counter, keys, masks, slot_tris, p, tri);
  else if (f.d == 1u) mv_voxelize_columns(ax, ay, az, bx, by, bz, cx, cy, cz, f, pl, 1u, first, last, counter, keys, masks, slot_tris, p, tri);
  else mv_voxelize_columns(ax, ay, az, bx, by, bz, cx, cy, cz, f, pl, 2u, first, last, counter, keys, masks, slot_tris, p, tri);
}

#endif
