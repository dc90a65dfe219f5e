/* Voxel colours of meshes (docs/colour.md), written once for the host, OpenCL C and GLSL. A voxel's colour is the
 * colour at the point nearest its centre on any triangle that overlaps it (the voxelizer's own overlap test),
 * ties to the lowest triangle index; the colour at a point is its triangle's vertex colours interpolated there.
 *
 * The voxelizer records its fragments: per (triangle, brick) met, the brick's key, the voxels the triangle sets
 * there and the triangle (voxelize.h, record_tris). Sorted by key, a brick's fragments are one run. A run of at
 * most MV_MESH_WHOLE_RUN fragments is read by a work-item per voxel of its brick (the lanes of a subgroup mostly
 * share a brick, so they walk the same run): the (squared distance, triangle) minimum over the fragments holding
 * the voxel, and its colour there. A longer run (or any, when the triangles span batches) goes in windows of
 * sorted fragments, a work-item each, whose minima combine by three passes of 32-bit atomic minima: the squared
 * distance's high word, then its low word among the windows holding the high one, then the triangle index among
 * those holding both. A positive double orders as its bits, so either way it is the exact (distance, index)
 * minimum, the same on every device whatever order the fragments came in; then a work-item per voxel of those
 * runs interpolates its colour. Distances: in grid units, from the triangles as the voxelizer takes them
 * (floats), in double. */
#ifndef MV_MESH_COLOUR_H
#define MV_MESH_COLOUR_H
#include "mesh_texture.h"
#include "morton.h" /* included by voxelize.h, after MvVoxelizeParams */

#define MV_MESH_DONE 0xfffffffeu /* a voxel's triangle plane once its colour is written */
#define MV_MESH_FRAGMENTS_PER_ITEM 16u /* a window of sorted fragments in a long run's passes */
#define MV_MESH_WHOLE_RUN 48u /* the longest run read per voxel (48 closest points at most, in lavapipe's loop cap) */

/* `bmeta`: per brick (sorted by key, as in `bkeys`) its voxel mask and first voxel; voxel i of its mask (Morton
 * order in the brick) is that + the mask's bits below i. `best`: planes of n words, the distance's high words,
 * its low words, the triangles (all ones: none yet). */

/* The point of a triangle nearest a point: its squared distance, b's and c's barycentric weights (a's: 1 - both). */
MV_STRUCT_BEGIN(MvClosest)
  mv_f64 d2;
  mv_f64 wb;
  mv_f64 wc;
MV_STRUCT_END(MvClosest)

/* What every nearest point on a triangle shares, once per triangle (mesh_triangle_terms): with ab = b - a and
 * ac = c - a, the Gram terms ab.ab, ab.ac and ac.ac, and 1 / (ab.ab ac.ac - (ab.ac)^2) (0 where that is not
 * positive: no area). `terms`: MV_MESH_TERMS doubles a triangle of the batch. */
#define MV_MESH_TERMS 4u
MV_INLINE void mv_mesh_triangle_terms(MvBufF32 tris, MvBufF64 terms, MvVoxelizeParams p, mv_u32 gid, mv_u32 gsize) {
  for (mv_u32 t = gid; t < p.batch_tris; t += gsize) {
    mv_u32 r = 9u * t;
    MV_PRECISE mv_f64 ax = MV_F64(MV_LD(tris, r)), ay = MV_F64(MV_LD(tris, r + 1u)), az = MV_F64(MV_LD(tris, r + 2u));
    MV_PRECISE mv_f64 abx = MV_F64(MV_LD(tris, r + 3u)) - ax, aby = MV_F64(MV_LD(tris, r + 4u)) - ay,
                      abz = MV_F64(MV_LD(tris, r + 5u)) - az;
    MV_PRECISE mv_f64 acx = MV_F64(MV_LD(tris, r + 6u)) - ax, acy = MV_F64(MV_LD(tris, r + 7u)) - ay,
                      acz = MV_F64(MV_LD(tris, r + 8u)) - az;
    MV_PRECISE mv_f64 e00 = abx * abx + aby * aby + abz * abz, e01 = abx * acx + aby * acy + abz * acz,
                      e11 = acx * acx + acy * acy + acz * acz;
    MV_PRECISE mv_f64 area = e00 * e11 - e01 * e01;
    MV_ST(terms, MV_MESH_TERMS * t, e00);
    MV_ST(terms, MV_MESH_TERMS * t + 1u, e01);
    MV_ST(terms, MV_MESH_TERMS * t + 2u, e11);
    MV_ST(terms, MV_MESH_TERMS * t + 3u, area > 0.0 ? 1.0 / area : 0.0);
  }
}

/* The point of the batch's triangle t (abc) nearest p (Ericson, Real-Time Collision Detection 5.1.5, its dot
 * products of p - b and p - c taken from the Gram terms: the same operations in the same order everywhere, so
 * every device gets the same bits); a triangle of no area falls to an edge or end. */
MV_INLINE MvClosest mv_closest_on_triangle(MvBufF32 tris, MvBufF64 terms, mv_u32 t, mv_f64 px, mv_f64 py, mv_f64 pz) {
  mv_u32 r = 9u * t, g = MV_MESH_TERMS * t;
  MV_PRECISE mv_f64 ax = MV_F64(MV_LD(tris, r)), ay = MV_F64(MV_LD(tris, r + 1u)), az = MV_F64(MV_LD(tris, r + 2u));
  MV_PRECISE mv_f64 abx = MV_F64(MV_LD(tris, r + 3u)) - ax, aby = MV_F64(MV_LD(tris, r + 4u)) - ay,
                    abz = MV_F64(MV_LD(tris, r + 5u)) - az;
  MV_PRECISE mv_f64 acx = MV_F64(MV_LD(tris, r + 6u)) - ax, acy = MV_F64(MV_LD(tris, r + 7u)) - ay,
                    acz = MV_F64(MV_LD(tris, r + 8u)) - az;
  MV_PRECISE mv_f64 apx = px - ax, apy = py - ay, apz = pz - az;
  MV_PRECISE mv_f64 d1 = abx * apx + aby * apy + abz * apz;
  MV_PRECISE mv_f64 d2 = acx * apx + acy * apy + acz * apz;
  mv_f64 e01 = MV_LD(terms, g + 1u), inv = MV_LD(terms, g + 3u);
  MV_PRECISE mv_f64 d3 = d1 - MV_LD(terms, g), d4 = d2 - e01, d5 = d1 - e01, d6 = d2 - MV_LD(terms, g + 2u);
  MV_PRECISE mv_f64 vc = d1 * d4 - d3 * d2;
  MV_PRECISE mv_f64 vb = d5 * d2 - d1 * d6;
  MV_PRECISE mv_f64 va = d3 * d6 - d5 * d4;
  mv_f64 v = 0.0, w = 0.0;
  if (d1 <= 0.0 && d2 <= 0.0) { /* vertex a */
  } else if (d3 >= 0.0 && d4 <= d3) {
    v = 1.0;
  } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    v = d1 / (d1 - d3);
  } else if (d6 >= 0.0 && d5 <= d6) {
    w = 1.0;
  } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    w = d2 / (d2 - d6);
  } else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    MV_PRECISE mv_f64 s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    v = 1.0 - s;
    w = s;
  } else if (inv > 0.0) { /* inside: va + vb + vc is ab.ab ac.ac - (ab.ac)^2 */
    v = vb * inv;
    w = vc * inv;
  } else { /* no area and p beside it: the nearer end of the longest edge, a or c (its middle is caught above) */
    w = d2 > 0.0 ? 1.0 : 0.0;
  }
  MV_PRECISE mv_f64 qx = ax + abx * v + acx * w, qy = ay + aby * v + acy * w, qz = az + abz * v + acz * w;
  MV_PRECISE mv_f64 dx = px - qx, dy = py - qy, dz = pz - qz;
  MvClosest q;
  q.d2 = dx * dx + dy * dy + dz * dz;
  q.wb = v;
  q.wc = w;
  return q;
}

/* The brick with key `key` among the `n` sorted keys (it is there: the voxels came from the same walk). */
MV_INLINE mv_u32 mv_find_brick(MvBufU64 bkeys, mv_u32 n, mv_u64 key) {
  mv_u32 lo = 0u, hi = n;
  while (hi - lo > 1u) {
    mv_u32 mid = lo + (hi - lo) / 2u;
    if (MV_LD(bkeys, mid) <= key) lo = mid;
    else hi = mid;
  }
  return lo;
}

/* The index of voxel `bit` (Morton order inside the brick) of brick b. */
MV_INLINE mv_u32 mv_brick_voxel(MvBufU64 bmeta, mv_u32 b, mv_u32 bit) {
  mv_u64 mask = MV_LD(bmeta, 2u * b);
  mv_u64 below = bit == 0u ? MV_U64(0u) : mask & (~MV_U64(0u) >> (64u - bit));
  return MV_U32(MV_LD(bmeta, 2u * b + 1u)) + MV_POPCOUNT(MV_U32(below)) + MV_POPCOUNT(MV_U32(below >> 32));
}

/* A voxel's best fragment: its squared distance, its nearest point's weights, its triangle (all ones: none). */
MV_STRUCT_BEGIN(MvBestFragment)
  mv_f64 d2;
  mv_f64 wb;
  mv_f64 wc;
  mv_u32 tri;
MV_STRUCT_END(MvBestFragment)

/* Voxel `bit` of the brick with key `key`: the (squared distance, triangle) minimum over fragments [s, e) that
 * hold it and whose triangle is in this batch. */
MV_INLINE MvBestFragment mv_mesh_voxel_best(MvBufF32 tris, MvBufF64 terms, MvBufU64 fmasks, MvBufU32 ftris, mv_u32 s,
                                            mv_u32 e, mv_u64 key, mv_u32 bit, MvVoxelizeParams p) {
  mv_f64 px = MV_F64(4u * mv_morton3_64_axis(key, 0u) + ((bit & 1u) | ((bit >> 2) & 2u))) + 0.5;
  mv_f64 py = MV_F64(4u * mv_morton3_64_axis(key, 1u) + (((bit >> 1) & 1u) | ((bit >> 3) & 2u))) + 0.5;
  mv_f64 pz = MV_F64(4u * mv_morton3_64_axis(key, 2u) + (((bit >> 2) & 1u) | ((bit >> 4) & 2u))) + 0.5;
  MvBestFragment best;
  best.d2 = 0.0;
  best.wb = 0.0;
  best.wc = 0.0;
  best.tri = 0xffffffffu;
  for (mv_u32 f = s; f < e; ++f) {
    if (((MV_LD(fmasks, f) >> bit) & MV_U64(1u)) == MV_U64(0u)) continue;
    mv_u32 tri = MV_LD(ftris, f), t = tri - p.tri_base;
    if (t >= p.batch_tris) continue;
    MvClosest q = mv_closest_on_triangle(tris, terms, t, px, py, pz);
    if (best.tri == 0xffffffffu || q.d2 < best.d2 || (q.d2 == best.d2 && tri < best.tri)) {
      best.d2 = q.d2;
      best.wb = q.wb;
      best.wc = q.wc;
      best.tri = tri;
    }
  }
  return best;
}

/* Pass p.colour_pass of a long run's fragments [s, e) (a window's share): each voxel's minimum, into the minima. */
MV_INLINE void mv_mesh_run_share(MvBufF32 tris, MvBufF64 terms, MvBufU64 fkeys, MvBufU64 fmasks, MvBufU32 ftris,
                                 MvBufU64 bkeys, MvBufU64 bmeta, MvBufU32 best, MvVoxelizeParams p, mv_u32 s, mv_u32 e) {
  mv_u32 n = p.capacity;
  mv_u64 key = MV_LD(fkeys, s), any = MV_U64(0u);
  for (mv_u32 f = s; f < e; ++f) any |= MV_LD(fmasks, f);
  mv_u32 b = mv_find_brick(bkeys, p.bricks, key);
  for (mv_u32 bit = 0u; bit < 64u; ++bit) {
    if (((any >> bit) & MV_U64(1u)) == MV_U64(0u)) continue;
    MvBestFragment v = mv_mesh_voxel_best(tris, terms, fmasks, ftris, s, e, key, bit, p);
    mv_u32 tri = v.tri, at = mv_brick_voxel(bmeta, b, bit), hi = MV_DBITS_HI(v.d2), lo = MV_DBITS_LO(v.d2);
    if (tri == 0xffffffffu) continue;
    if (p.colour_pass == 1u) MV_ATOMIC_MIN(best, at, hi);
    else if (p.colour_pass == 2u && MV_LD(best, at) == hi) MV_ATOMIC_MIN(best, n + at, lo);
    else if (p.colour_pass == 3u && MV_LD(best, at) == hi && MV_LD(best, n + at) == lo)
      MV_ATOMIC_MIN(best, 2u * n + at, tri);
  }
}

/* Pass p.colour_pass (1 to 3; 0 only sets `seen` to 1 if there is one, passes 1 to 3 never touch it) of the long
 * runs among the p.items fragments sorted by key (`fkeys`, their masks and triangles; long: past MV_MESH_WHOLE_RUN
 * fragments, or every run with p.split_runs), a work-item per window of MV_MESH_FRAGMENTS_PER_ITEM of them: each
 * window's share of a long run into `best` (p.capacity voxels, p.bricks bricks). A window sees whether a run is
 * long from at most MV_MESH_WHOLE_RUN keys either side. */
MV_INLINE void mv_mesh_best_fragments(MvBufF32 tris, MvBufF64 terms, MvBufU64 fkeys, MvBufU64 fmasks, MvBufU32 ftris,
                                      MvBufU64 bkeys, MvBufU64 bmeta, MvBufU32 best, MvBufU32 seen, MvVoxelizeParams p,
                                      mv_u32 gid, mv_u32 gsize) {
  mv_u32 longest = p.split_runs != 0u ? 0u : MV_MESH_WHOLE_RUN, n = p.items;
  mv_u32 items = (n + MV_MESH_FRAGMENTS_PER_ITEM - 1u) / MV_MESH_FRAGMENTS_PER_ITEM;
  for (mv_u32 c = gid; c < items; c += gsize) {
    mv_u32 s = c * MV_MESH_FRAGMENTS_PER_ITEM, w1 = MV_MIN(n, s + MV_MESH_FRAGMENTS_PER_ITEM);
    while (s < w1) { /* each run the window meets: its length, counted up to longest + 1 */
      mv_u64 key = MV_LD(fkeys, s);
      mv_u32 len = 1u, e = s + 1u;
      for (mv_u32 b = s; b > 0u && len <= longest && MV_LD(fkeys, b - 1u) == key; --b) len = len + 1u;
      for (; e < n && len <= longest && MV_LD(fkeys, e) == key; ++e) len = len + 1u;
      if (len > longest) { /* long: this window's share */
        if (p.colour_pass == 0u) MV_ST(seen, 0u, 1u);
        for (e = s; e < w1 && MV_LD(fkeys, e) == key; ++e) {
        }
        if (p.colour_pass != 0u) mv_mesh_run_share(tris, terms, fkeys, fmasks, ftris, bkeys, bmeta, best, p, s, e);
      }
      s = e;
    }
  }
}

#if !defined(MV_CPP)
/* Each voxel's key, a work-item per brick (p.bricks of them): its at most 64 voxels, from its first voxel on. */
MV_INLINE void mv_mesh_voxel_keys(MvBufU64 bkeys, MvBufU64 bmeta, MvBufU64 voxel_keys, MvBufU32 voxel_brick,
                                  MvVoxelizeParams p, mv_u32 gid, mv_u32 gsize) {
  for (mv_u32 b = gid; b < p.bricks; b += gsize) {
    mv_u64 mask = MV_LD(bmeta, 2u * b), key = MV_LD(bkeys, b) << 6;
    mv_u32 at = MV_U32(MV_LD(bmeta, 2u * b + 1u));
    for (mv_u32 word = 0u; word < 2u; ++word) /* the set bits only, lowest first, a 32-bit half at a time */
      for (mv_u32 m = MV_U32(mask >> (32u * word)); m != 0u; m &= m - 1u) {
        MV_ST(voxel_keys, at, key | MV_U64(32u * word + MV_FIND_LSB(m)));
        MV_ST(voxel_brick, at, b);
        at = at + 1u;
      }
  }
}

/* Voxels [0, p.items) whose brick's run of fragments (`run_starts`: per brick its first sorted fragment, then the
 * fragments' count) is at most MV_MESH_WHOLE_RUN long: the best of those holding the voxel, and the colour there
 * into `voxel_rgb`; with p.colour_pass 1 (there are long runs) its triangle (`best`'s third plane of p.capacity
 * words) becomes MV_MESH_DONE. With p.split_runs nothing: every run goes through the passes. */
MV_INLINE void mv_mesh_voxel_best_colours(MvBufF32 tris, MvBufF64 terms, MvBufU64 fmasks, MvBufU32 ftris,
                                          MvBufU32 run_starts, MvBufU64 voxel_keys, MvBufU32 voxel_brick, MvBufU32 attr,
                                          MvBufU32 texels, MvBufU32 best, MvBufU32 voxel_rgb, MvVoxelizeParams p,
                                          mv_u32 gid, mv_u32 gsize) {
  if (p.split_runs != 0u) return;
  for (mv_u32 i = gid; i < p.items; i += gsize) {
    mv_u32 b = MV_LD(voxel_brick, i), s = MV_LD(run_starts, b), e = MV_LD(run_starts, b + 1u);
    if (e - s > MV_MESH_WHOLE_RUN) continue;
    mv_u64 key = MV_LD(voxel_keys, i);
    MvBestFragment v = mv_mesh_voxel_best(tris, terms, fmasks, ftris, s, e, key >> 6, MV_U32(key & MV_U64(63u)), p);
    MV_ST(voxel_rgb, i, mv_mesh_colour_at(attr, texels, v.tri - p.tri_base, v.wb, v.wc));
    if (p.colour_pass != 0u) MV_ST(best, 2u * p.capacity + i, MV_MESH_DONE);
  }
}

/* Voxels [0, p.items): where the voxel's best fragment's triangle is one of this batch's (`tris`, 9 floats each in
 * grid units, and `attr`; from triangle p.tri_base on, p.batch_tris of them), its colour at that triangle's point
 * nearest its centre. `best`: the triangle plane (MV_MESH_DONE: coloured already); `voxel_keys`: each voxel's key
 * (mv_mesh_voxel_keys). */
MV_INLINE void mv_mesh_voxel_colours(MvBufF32 tris, MvBufF64 terms, MvBufU32 attr, MvBufU32 texels, MvBufU32 best,
                                     MvBufU64 voxel_keys, MvBufU32 voxel_rgb, MvVoxelizeParams p, mv_u32 gid,
                                     mv_u32 gsize) {
  for (mv_u32 i = gid; i < p.items; i += gsize) {
    mv_u32 t = MV_LD(best, i) - p.tri_base;
    if (t >= p.batch_tris) continue;
    mv_u64 key = MV_LD(voxel_keys, i);
    mv_u32 kx = mv_morton3_64_axis(key, 0u), ky = mv_morton3_64_axis(key, 1u), kz = mv_morton3_64_axis(key, 2u);
    MvClosest q = mv_closest_on_triangle(tris, terms, t, MV_F64(kx) + 0.5, MV_F64(ky) + 0.5, MV_F64(kz) + 0.5);
    MV_ST(voxel_rgb, i, mv_mesh_colour_at(attr, texels, t, q.wb, q.wc));
  }
}
#endif

#endif /* MV_MESH_COLOUR_H */
