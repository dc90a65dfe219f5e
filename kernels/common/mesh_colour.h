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
#include "floor64.h"
#include "morton.h" /* included by voxelize.h, after MvVoxelizeParams */

#define MV_MESH_ATTR_WORDS 12u /* per triangle: 3 vertex colours, 6 texture coordinates, the texture, 2 spare */
#define MV_NO_TEXTURE 0xffffffffu
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

/* The point of triangle abc nearest p (Ericson, Real-Time Collision Detection 5.1.5, the same operations in the
 * same order everywhere so every device gets the same bits); a triangle of no area falls to an edge or end. */
MV_INLINE MvClosest mv_closest_on_triangle(mv_f64 ax, mv_f64 ay, mv_f64 az, mv_f64 bx, mv_f64 by, mv_f64 bz,
                                           mv_f64 cx, mv_f64 cy, mv_f64 cz, mv_f64 px, mv_f64 py, mv_f64 pz) {
  MV_PRECISE mv_f64 abx = bx - ax, aby = by - ay, abz = bz - az;
  MV_PRECISE mv_f64 acx = cx - ax, acy = cy - ay, acz = cz - az;
  MV_PRECISE mv_f64 apx = px - ax, apy = py - ay, apz = pz - az;
  MV_PRECISE mv_f64 d1 = abx * apx + aby * apy + abz * apz;
  MV_PRECISE mv_f64 d2 = acx * apx + acy * apy + acz * apz;
  MV_PRECISE mv_f64 bpx = px - bx, bpy = py - by, bpz = pz - bz;
  MV_PRECISE mv_f64 d3 = abx * bpx + aby * bpy + abz * bpz;
  MV_PRECISE mv_f64 d4 = acx * bpx + acy * bpy + acz * bpz;
  MV_PRECISE mv_f64 cpx = px - cx, cpy = py - cy, cpz = pz - cz;
  MV_PRECISE mv_f64 d5 = abx * cpx + aby * cpy + abz * cpz;
  MV_PRECISE mv_f64 d6 = acx * cpx + acy * cpy + acz * cpz;
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
    MV_PRECISE mv_f64 t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    v = 1.0 - t;
    w = t;
  } else if (va + vb + vc > 0.0) {
    MV_PRECISE mv_f64 inv = 1.0 / (va + vb + vc);
    v = vb * inv;
    w = vc * inv;
  } else { /* no area and p beside it: the nearer end of the longest edge, a or c (its middle is caught above) */
    w = d2 > 0.0 ? 1.0 : 0.0;
  }
  MV_PRECISE mv_f64 qx = ax + abx * v + acx * w, qy = ay + aby * v + acy * w, qz = az + abz * v + acz * w;
  MV_PRECISE mv_f64 dx = px - qx, dy = py - qy, dz = pz - qz;
  MvClosest r;
  r.d2 = dx * dx + dy * dy + dz * dz;
  r.wb = v;
  r.wc = w;
  return r;
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
MV_INLINE MvBestFragment mv_mesh_voxel_best(MvBufF32 tris, MvBufU64 fmasks, MvBufU32 ftris, mv_u32 s, mv_u32 e,
                                            mv_u64 key, mv_u32 bit, MvVoxelizeParams p) {
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
    mv_u32 tri = MV_LD(ftris, f), t = tri - p.tri_base, r = 9u * t;
    if (t >= p.batch_tris) continue;
    MvClosest q = mv_closest_on_triangle(
        MV_F64(MV_LD(tris, r)), MV_F64(MV_LD(tris, r + 1u)), MV_F64(MV_LD(tris, r + 2u)), MV_F64(MV_LD(tris, r + 3u)),
        MV_F64(MV_LD(tris, r + 4u)), MV_F64(MV_LD(tris, r + 5u)), MV_F64(MV_LD(tris, r + 6u)),
        MV_F64(MV_LD(tris, r + 7u)), MV_F64(MV_LD(tris, r + 8u)), px, py, pz);
    if (best.tri == 0xffffffffu || q.d2 < best.d2 || (q.d2 == best.d2 && tri < best.tri)) {
      best.d2 = q.d2;
      best.wb = q.wb;
      best.wc = q.wc;
      best.tri = tri;
    }
  }
  return best;
}

/* floor(c + 0.5) clamped to [0, 255]: a channel rounded half up (truncation is floor where it is not clamped). */
MV_INLINE mv_u32 mv_channel_byte(mv_f64 c) {
  return c + 0.5 < 1.0 ? 0u : c + 0.5 >= 255.0 ? 255u : MV_U32(c + 0.5);
}

/* One channel of the colour at weights (1 - wb - wc, wb, wc) of vertex colours ca, cb, cc (0xBBGGRR), rounded. */
MV_INLINE mv_u32 mv_mesh_channel(mv_u32 ca, mv_u32 cb, mv_u32 cc, mv_u32 shift, mv_f64 wb, mv_f64 wc) {
  MV_PRECISE mv_f64 x = MV_F64((ca >> shift) & 255u) * (1.0 - wb - wc) + MV_F64((cb >> shift) & 255u) * wb +
                        MV_F64((cc >> shift) & 255u) * wc;
  return mv_channel_byte(x);
}

/* Texture `tex` sampled bilinearly at (u, v) (v = 0 at the bottom row; repeating; channels rounded half up): texel
 * centres at half-integers, the four around the point weighted by their distances, wrapping at the edges. `texels`:
 * the count, then per texture its first texel's word, width and height, then the texels (0xBBGGRR, top row first). */
MV_INLINE mv_u32 mv_texture_rgb(MvBufU32 texels, mv_u32 tex, mv_f64 u, mv_f64 v) {
  mv_u32 base = MV_LD(texels, 1u + 3u * tex), w = MV_LD(texels, 2u + 3u * tex), h = MV_LD(texels, 3u + 3u * tex);
  MV_PRECISE mv_f64 x = (u - mv_floor64(u)) * MV_F64(w) - 0.5, y = (1.0 - (v - mv_floor64(v))) * MV_F64(h) - 0.5;
  mv_f64 x0 = mv_floor64(x), y0 = mv_floor64(y);
  MV_PRECISE mv_f64 fx = x - x0, fy = y - y0;
  /* x0 is in [-1, w - 1] and y0 in [-1, h - 1]; the clamps only keep a NaN coordinate inside the texture. */
  mv_i32 ix = MV_I32(x0), iy = MV_I32(y0);
  mv_u32 xa = ix < 0 ? w - 1u : MV_MIN(MV_U32(ix), w - 1u), ya = iy < 0 ? h - 1u : MV_MIN(MV_U32(iy), h - 1u);
  mv_u32 xb = ix + 1 >= MV_I32(w) ? 0u : MV_MIN(MV_U32(ix + 1), w - 1u);
  mv_u32 yb = iy + 1 >= MV_I32(h) ? 0u : MV_MIN(MV_U32(iy + 1), h - 1u);
  mv_u32 t00 = MV_LD(texels, base + ya * w + xa), t10 = MV_LD(texels, base + ya * w + xb);
  mv_u32 t01 = MV_LD(texels, base + yb * w + xa), t11 = MV_LD(texels, base + yb * w + xb), rgb = 0u;
  for (mv_u32 shift = 0u; shift < 24u; shift += 8u) {
    mv_f64 c00 = MV_F64((t00 >> shift) & 255u), c10 = MV_F64((t10 >> shift) & 255u);
    mv_f64 c01 = MV_F64((t01 >> shift) & 255u), c11 = MV_F64((t11 >> shift) & 255u);
    MV_PRECISE mv_f64 c = (c00 * (1.0 - fx) + c10 * fx) * (1.0 - fy) + (c01 * (1.0 - fx) + c11 * fx) * fy;
    rgb |= mv_channel_byte(c) << shift;
  }
  return rgb;
}

/* The colour (0xBBGGRR) of the batch's triangle t at weights (1 - wb - wc, wb, wc): its vertex colours
 * interpolated, or its texture sampled at its interpolated coordinates. `attr`: MV_MESH_ATTR_WORDS a triangle (3
 * vertex colours, 6 texture coordinates as float bits, the texture). */
MV_INLINE mv_u32 mv_mesh_colour_at(MvBufU32 attr, MvBufU32 texels, mv_u32 t, mv_f64 wb, mv_f64 wc) {
  mv_u32 a = MV_MESH_ATTR_WORDS * t, tex = MV_LD(attr, a + 9u);
  if (tex == MV_NO_TEXTURE) {
    mv_u32 ca = MV_LD(attr, a), cb = MV_LD(attr, a + 1u), cc = MV_LD(attr, a + 2u);
    return mv_mesh_channel(ca, cb, cc, 0u, wb, wc) | (mv_mesh_channel(ca, cb, cc, 8u, wb, wc) << 8) |
           (mv_mesh_channel(ca, cb, cc, 16u, wb, wc) << 16);
  }
  MV_PRECISE mv_f64 wa = 1.0 - wb - wc;
  MV_PRECISE mv_f64 u = MV_F64(MV_BITSF(MV_LD(attr, a + 3u))) * wa + MV_F64(MV_BITSF(MV_LD(attr, a + 5u))) * wb +
                        MV_F64(MV_BITSF(MV_LD(attr, a + 7u))) * wc;
  MV_PRECISE mv_f64 v = MV_F64(MV_BITSF(MV_LD(attr, a + 4u))) * wa + MV_F64(MV_BITSF(MV_LD(attr, a + 6u))) * wb +
                        MV_F64(MV_BITSF(MV_LD(attr, a + 8u))) * wc;
  return mv_texture_rgb(texels, tex, u, v);
}

/* Pass p.colour_pass of a long run's fragments [s, e) (a window's share): each voxel's minimum, into the minima. */
MV_INLINE void mv_mesh_run_share(MvBufF32 tris, MvBufU64 fkeys, MvBufU64 fmasks, MvBufU32 ftris, MvBufU64 bkeys,
                                 MvBufU64 bmeta, MvBufU32 best, MvVoxelizeParams p, mv_u32 s, mv_u32 e) {
  mv_u32 n = p.capacity;
  mv_u64 key = MV_LD(fkeys, s), any = MV_U64(0u);
  for (mv_u32 f = s; f < e; ++f) any |= MV_LD(fmasks, f);
  mv_u32 b = mv_find_brick(bkeys, p.bricks, key);
  for (mv_u32 bit = 0u; bit < 64u; ++bit) {
    if (((any >> bit) & MV_U64(1u)) == MV_U64(0u)) continue;
    MvBestFragment v = mv_mesh_voxel_best(tris, fmasks, ftris, s, e, key, bit, p);
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
MV_INLINE void mv_mesh_best_fragments(MvBufF32 tris, MvBufU64 fkeys, MvBufU64 fmasks, MvBufU32 ftris, MvBufU64 bkeys,
                                      MvBufU64 bmeta, MvBufU32 best, MvBufU32 seen, MvVoxelizeParams p, mv_u32 gid,
                                      mv_u32 gsize) {
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
        if (p.colour_pass != 0u) mv_mesh_run_share(tris, fkeys, fmasks, ftris, bkeys, bmeta, best, p, s, e);
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
    for (mv_u32 bit = 0u; bit < 64u; ++bit)
      if (((mask >> bit) & MV_U64(1u)) != MV_U64(0u)) {
        MV_ST(voxel_keys, at, key | MV_U64(bit));
        MV_ST(voxel_brick, at, b);
        at = at + 1u;
      }
  }
}

/* Voxels [0, p.items) whose brick's run of fragments (`run_starts`: per brick its first sorted fragment, then the
 * fragments' count) is at most MV_MESH_WHOLE_RUN long: the best of those holding the voxel, and the colour there
 * into `voxel_rgb`; with p.colour_pass 1 (there are long runs) its triangle (`best`'s third plane of p.capacity
 * words) becomes MV_MESH_DONE. With p.split_runs nothing: every run goes through the passes. */
MV_INLINE void mv_mesh_voxel_best_colours(MvBufF32 tris, MvBufU64 fmasks, MvBufU32 ftris, MvBufU32 run_starts,
                                          MvBufU64 voxel_keys, MvBufU32 voxel_brick, MvBufU32 attr, MvBufU32 texels,
                                          MvBufU32 best, MvBufU32 voxel_rgb, MvVoxelizeParams p, mv_u32 gid,
                                          mv_u32 gsize) {
  if (p.split_runs != 0u) return;
  for (mv_u32 i = gid; i < p.items; i += gsize) {
    mv_u32 b = MV_LD(voxel_brick, i), s = MV_LD(run_starts, b), e = MV_LD(run_starts, b + 1u);
    if (e - s > MV_MESH_WHOLE_RUN) continue;
    mv_u64 key = MV_LD(voxel_keys, i);
    MvBestFragment v = mv_mesh_voxel_best(tris, fmasks, ftris, s, e, key >> 6, MV_U32(key & MV_U64(63u)), p);
    MV_ST(voxel_rgb, i, mv_mesh_colour_at(attr, texels, v.tri - p.tri_base, v.wb, v.wc));
    if (p.colour_pass != 0u) MV_ST(best, 2u * p.capacity + i, MV_MESH_DONE);
  }
}

/* Voxels [0, p.items): where the voxel's best fragment's triangle is one of this batch's (`tris`, 9 floats each in
 * grid units, and `attr`; from triangle p.tri_base on, p.batch_tris of them), its colour at that triangle's point
 * nearest its centre. `best`: the triangle plane (MV_MESH_DONE: coloured already); `voxel_keys`: each voxel's key
 * (mv_mesh_voxel_keys). */
MV_INLINE void mv_mesh_voxel_colours(MvBufF32 tris, MvBufU32 attr, MvBufU32 texels, MvBufU32 best,
                                     MvBufU64 voxel_keys, MvBufU32 voxel_rgb, MvVoxelizeParams p, mv_u32 gid,
                                     mv_u32 gsize) {
  for (mv_u32 i = gid; i < p.items; i += gsize) {
    mv_u32 t = MV_LD(best, i) - p.tri_base;
    if (t >= p.batch_tris) continue;
    mv_u64 key = MV_LD(voxel_keys, i);
    mv_u32 kx = mv_morton3_64_axis(key, 0u), ky = mv_morton3_64_axis(key, 1u), kz = mv_morton3_64_axis(key, 2u);
    mv_u32 r = 9u * t;
    MvClosest q = mv_closest_on_triangle(
        MV_F64(MV_LD(tris, r)), MV_F64(MV_LD(tris, r + 1u)), MV_F64(MV_LD(tris, r + 2u)), MV_F64(MV_LD(tris, r + 3u)),
        MV_F64(MV_LD(tris, r + 4u)), MV_F64(MV_LD(tris, r + 5u)), MV_F64(MV_LD(tris, r + 6u)),
        MV_F64(MV_LD(tris, r + 7u)), MV_F64(MV_LD(tris, r + 8u)), MV_F64(kx) + 0.5, MV_F64(ky) + 0.5, MV_F64(kz) + 0.5);
    MV_ST(voxel_rgb, i, mv_mesh_colour_at(attr, texels, t, q.wb, q.wc));
  }
}
#endif

#endif /* MV_MESH_COLOUR_H */
