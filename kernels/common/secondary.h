/* Secondary rays from primary hits (shadow rays toward a directional light, ambient-occlusion rays), written
 * once for the host, OpenCL C and GLSL. Only hits on a face cast them: secondary_flags marks those, the shared
 * stream compaction lists them, and secondary_rays makes one ray per listed hit, so the trace that follows has
 * no idle work-items or lanes. They start on the face the primary ray hit, moved off it by 1/256 of
 * the hit cell and then `lead` hit cells along their direction (a voxelized surface is a staircase: without
 * the lead a ray toward a light at a shallow angle meets the next step of its own surface), and keep the
 * primary's LOD (lod_t = primary lod_t + t). AO directions come from a table of
 * cosine-weighted unit vectors around +z (host-made), turned to the face normal by permuting axes (exact);
 * pixel p's sample k uses entry (hash(p) + k * stride) & mask, so every device draws the same sequence. */
#ifndef MV_SECONDARY_H
#define MV_SECONDARY_H
#include "trace.h"

#define MV_SECONDARY_SHADOW 0u
#define MV_SECONDARY_AO 1u

MV_STRUCT_BEGIN(MvSecondaryParams)
  mv_u32 first; /* listed hits [first, first + count) in this dispatch (secondary_flags: primary rays) */
  mv_u32 count;
  mv_u32 levels;
  mv_u32 camera; /* primaries are camera rays (1) or come from the ray buffer (0) */
  mv_u32 width;
  mv_u32 kind;   /* MV_SECONDARY_SHADOW or MV_SECONDARY_AO */
  mv_u32 sample_k; /* AO: sample number k */
  mv_u32 stride; /* AO: table entries between samples */
  mv_u32 mask;   /* AO: table entries - 1 (a power of two minus one) */
  mv_f32 lx; mv_f32 ly; mv_f32 lz; /* shadow: unit direction toward the light (root-cube axes) */
  mv_f32 tmax;   /* shadow: how far to look; AO: the occlusion radius (root cube = 1) */
  mv_f32 lead;   /* start this many hit cells along the ray: steps past the voxel staircase of the surface */
  mv_u32 block;  /* nonzero: each work-item takes this many consecutive items (CPU devices), else grid-stride */
  mv_u32 pad2;
MV_STRUCT_END(MvSecondaryParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvSecondaryParams, 64);
MV_LAYOUT_AT(MvSecondaryParams, first, 0); MV_LAYOUT_AT(MvSecondaryParams, count, 4);
MV_LAYOUT_AT(MvSecondaryParams, levels, 8); MV_LAYOUT_AT(MvSecondaryParams, camera, 12);
MV_LAYOUT_AT(MvSecondaryParams, width, 16); MV_LAYOUT_AT(MvSecondaryParams, kind, 20);
MV_LAYOUT_AT(MvSecondaryParams, sample_k, 24); MV_LAYOUT_AT(MvSecondaryParams, stride, 28);
MV_LAYOUT_AT(MvSecondaryParams, mask, 32); MV_LAYOUT_AT(MvSecondaryParams, lx, 36);
MV_LAYOUT_AT(MvSecondaryParams, ly, 40); MV_LAYOUT_AT(MvSecondaryParams, lz, 44);
MV_LAYOUT_AT(MvSecondaryParams, tmax, 48); MV_LAYOUT_AT(MvSecondaryParams, lead, 52);
MV_LAYOUT_AT(MvSecondaryParams, block, 56); MV_LAYOUT_AT(MvSecondaryParams, pad2, 60);
#endif

MV_INLINE mv_u32 mv_hash32(mv_u32 x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

/* An inactive ray (tmax < 0): traces to a miss at once. */
MV_INLINE MvRay mv_inactive_ray() {
  MvRay r;
  r.ox = 0.0f; r.oy = 0.0f; r.oz = 0.0f;
  r.dx = 1.0f; r.dy = 0.0f; r.dz = 0.0f;
  r.tmax = -1.0f;
  r.lod_t = 0.0f;
  return r;
}

/* Does a hit with this info word cast secondary rays (a hit on a face; a ray that starts inside a voxel has
 * none)? */
MV_INLINE bool mv_secondary_active(mv_u32 info) {
  return MV_INFO_STATUS(info) == MV_TRACE_HIT && MV_INFO_AXIS(info) != MV_AXIS_NONE;
}

/* The secondary ray of primary ray `pr` with hit `h` in direction (u, v, w) given in the hit face's frame
 * (w along the normal, u and v along the next two axes) when `in_face_frame` is 1, or (u, v, w) = (x, y, z) when 0. */
MV_INLINE MvRay mv_secondary_ray(MvRay pr, MvHit h, mv_u32 L, mv_u32 in_face_frame, mv_f32 u, mv_f32 v, mv_f32 w,
                                 mv_f32 tmax, mv_f32 lead) {
  mv_u32 axis = MV_INFO_AXIS(h.info);
  if (!mv_secondary_active(h.info)) return mv_inactive_ray();
  mv_f32 s = mv_cell_side(MV_INFO_LEVEL(h.info), L);
  bool negative = MV_INFO_NEGATIVE(h.info) != 0u;
  MV_PRECISE mv_f32 p[3];
  p[0] = pr.ox + h.t * pr.dx;
  p[1] = pr.oy + h.t * pr.dy;
  p[2] = pr.oz + h.t * pr.dz;
  mv_u32 cell = axis == 0u ? h.x : axis == 1u ? h.y : h.z;
  MV_PRECISE mv_f32 face = MV_F32(cell + (negative ? 0u : 1u)) * s;
  MV_PRECISE mv_f32 off = s * 0.00390625f;
  p[axis] = negative ? face - off : face + off;
  mv_f32 d[3];
  d[0] = u; d[1] = v; d[2] = w;
  if (in_face_frame != 0u) {
    d[axis] = negative ? -w : w;
    d[(axis + 1u) % 3u] = u;
    d[(axis + 2u) % 3u] = v;
  }
  MV_PRECISE mv_f32 step = lead * s;
  p[0] = p[0] + step * d[0];
  p[1] = p[1] + step * d[1];
  p[2] = p[2] + step * d[2];
  MvRay r;
  r.ox = p[0]; r.oy = p[1]; r.oz = p[2];
  r.dx = d[0]; r.dy = d[1]; r.dz = d[2];
  r.tmax = tmax;
  MV_PRECISE mv_f32 lod = pr.lod_t + h.t;
  r.lod_t = lod;
  return r;
}

/* The secondary ray of pixel / ray i for the parameters' kind and sample. */
MV_INLINE MvRay mv_make_secondary(MvRay pr, MvHit h, MvBufF32 table, mv_u32 i, MvSecondaryParams p) {
  if (p.kind == MV_SECONDARY_SHADOW) return mv_secondary_ray(pr, h, p.levels, 0u, p.lx, p.ly, p.lz, p.tmax, p.lead);
  mv_u32 e = (mv_hash32(i) + p.sample_k * p.stride) & p.mask;
  return mv_secondary_ray(pr, h, p.levels, 1u, MV_LD(table, 3u * e), MV_LD(table, 3u * e + 1u),
                          MV_LD(table, 3u * e + 2u), p.tmax, p.lead);
}

#if !defined(MV_CPP)
/* flags[i] = 1 where primary hit i casts secondary rays, for i in [first, first + count). */
MV_INLINE void mv_secondary_flags(MvBufU32 hits, MvBufU32 flags, MvSecondaryParams p, mv_u32 gid, mv_u32 gsize) {
  MvItems r = mv_items(p.block, gid, gsize, p.count);
  for (mv_u32 j = r.begin; j < r.end; j += r.step) {
    mv_u32 i = p.first + j;
    MV_ST(flags, i, mv_secondary_active(MV_LD(hits, MV_HIT_WORDS * i + 4u)) ? 1u : 0u); /* the info word */
  }
}

/* rays_out[j] = the secondary ray of listed hit j (primary ray listed[j]), for j in [first, first + count). */
MV_INLINE void mv_secondary_rays(MvBufF32 rays, MvBufF32 cam, MvBufU32 hits, MvBufU32 listed, MvBufF32 table,
                                 MvBufU32 rays_out, MvSecondaryParams p, mv_u32 gid, mv_u32 gsize) {
  MvItems r = mv_items(p.block, gid, gsize, p.count);
  for (mv_u32 k = r.begin; k < r.end; k += r.step) {
    mv_u32 j = p.first + k;
    mv_u32 i = MV_LD(listed, j);
    MvRay pr = p.camera == 1u ? mv_camera_ray(cam, i, p.width) : mv_load_ray(rays, i);
    /* AO samples hash the frame's pixel, so a frame rendered in tiles gets the same rays */
    mv_u32 pixel = p.camera == 1u ? mv_camera_pixel(cam, i) : i;
    mv_store_ray(rays_out, j, mv_make_secondary(pr, mv_load_hit(hits, i), table, pixel, p));
  }
}
#endif

#endif /* MV_SECONDARY_H */
