/* Ray traversal's records and parameters, shared by the host and the kernels (trace.h walks, secondary.h makes
 * secondary rays): the encodings' constants, the trace parameters, the ray, camera and hit records and how a
 * kernel reads its rays. Written once for the host, OpenCL C and GLSL. */
#ifndef MV_TRACE_TYPES_H
#define MV_TRACE_TYPES_H
#include "mv_lang.h"

#define MV_ENC_SVDAG 2u  /* also stands for svo and ussvdag: the same 32-bit word decode */
#define MV_ENC_SSVDAG 4u
#define MV_ENC_PAGED 8u  /* 32-bit word encodings read through the page cache (trace.h: mv_page_resolve) */
#define MV_ENC_PAGED_SSVDAG 12u /* ssvdag read through the page cache (host/formats/paging/paged_ssvdag.h) */
#define MV_TRACE_MISS 0u
#define MV_TRACE_HIT 1u
#define MV_TRACE_GAVE_UP 2u /* max_steps reached */
#define MV_AXIS_NONE 3u     /* hit at the ray's origin: no face */
#define MV_RAY_FLOATS 8u    /* ox oy oz dx dy dz tmax lod_t */
#define MV_HIT_WORDS 6u     /* t (float bits) x y z info steps */
#define MV_CAMERA_FLOATS 16u
/* The camera record (mv_camera_ray): where each of its vectors starts, then tmax */
#define MV_CAMERA_EYE 0u
#define MV_CAMERA_BASE 3u
#define MV_CAMERA_DU 6u
#define MV_CAMERA_DV 9u
#define MV_CAMERA_TMAX 12u
#define MV_CAMERA_FIRST 13u /* the pixel of ray 0 (float bits of a u32): a tile's rays index its own buffers */
#define MV_TRACE_PARAM_LEVELS 13u /* the parameters can hold where ssvdag levels 3 .. 15 start (every tree up
                                     to 64K^3); the push constants hold no more (128 bytes) */

/* info word of a hit record: status | face axis << 2 | (normal points to -axis) << 4 | level << 8 |
 * coarse << 13 (paged: the walk stopped at that cell because the page below it was missing) */
#define MV_INFO_COARSE_BIT (1u << 13)
#define MV_INFO_STATUS(i) ((i) & 3u)
#define MV_INFO_AXIS(i) (((i) >> 2) & 3u)
#define MV_INFO_NEGATIVE(i) (((i) >> 4) & 1u)
#define MV_INFO_LEVEL(i) (((i) >> 8) & 31u)
#define MV_INFO_COARSE(i) (((i) >> 13) & 1u)

/* The trace parameters' mode word: L (the root cube is 2^L voxels per axis, L <= 21) | camera << 5 (0: rays
 * from the ray buffer; 1: camera rays, ray index = pixel) | occlusion << 6 (0: hit records; 1: occlusion
 * counts, count[i] += 1 when ray i hits) | page shift << 8 (paged: log2 of the page size in words). One word for
 * the four leaves the push constants room for the level starts a paged ssvdag walk selects from. */
#define MV_TRACE_MODE(levels, camera, occlusion, page_shift)                                                     \
  ((levels) | ((camera) << 5) | ((occlusion) << 6) | ((page_shift) << 8))
#define MV_TRACE_LEVELS(p) ((p).mode & 31u)
#define MV_TRACE_CAMERA(p) (((p).mode >> 5) & 1u)
#define MV_TRACE_OCCLUSION(p) (((p).mode >> 6) & 1u)
#define MV_TRACE_PAGE_SHIFT(p) (((p).mode >> 8) & 31u)
/* With camera rays: each ray starts where the beam pre-pass says its tile's rays may (trace_beam.h), read after
 * the camera record, one float per MV_BEAM_TILE x MV_BEAM_TILE pixels of the frame in row order. */
#define MV_TRACE_MODE_BEAM (1u << 7)
#define MV_TRACE_BEAM(p) (((p).mode >> 7) & 1u)
#define MV_BEAM_TILE 4u
#define MV_BEAM_NOTHING 1e30f /* a tile start: none of its rays meets the cube */

/* How many tiles of `tile` pixels a side cover a frame. */
MV_INLINE mv_u32 mv_beam_tile_count(mv_u32 width, mv_u32 height, mv_u32 tile) {
  return ((width + tile - 1u) / tile) * ((height + tile - 1u) / tile);
}

MV_INLINE mv_u32 mv_beam_tile(mv_u32 pixel, mv_u32 width) {
  return (pixel / width / MV_BEAM_TILE) * ((width + MV_BEAM_TILE - 1u) / MV_BEAM_TILE) + (pixel % width) / MV_BEAM_TILE;
}

/* Paged traversal (MV_ENC_PAGED, MV_ENC_PAGED_SSVDAG): level_base's last two words carry the pass's stamp and
 * where the pages' runs start in the table's buffer (page_cache.h: runs). A paged ssvdag's level starts lie
 * just before its runs (table[runs - (L + 1) + l]: the first node of inner level l in 16-bit words, l = 3 .. L;
 * l = 2, the bricks, always 0), and the first MV_TRACE_PAGED_PARAM_LEVELS of them may come with the parameters
 * too, where the other words hold them for the resident walk. */
#define MV_TRACE_PAGE_STAMP 11
#define MV_TRACE_PAGE_RUNS 12
#define MV_TRACE_PAGED_PARAM_LEVELS 11u /* levels 3 .. 13: every tree up to 16K^3 */

/* A walk's variant (mv_trace), a constant of each trace kernel: an ssvdag's level starts come with the
 * parameters (else from memory: mv_level_base); paged, the walk stamps the slots it reads for the LRU (else a
 * cache with a slot for every page, preloaded, that never evicts: the stamping code alone, never run, costs
 * PoCL ~8 % and lavapipe ~15 % of the trace); a paged word stream's pointers count from their level's start
 * (else absolute: the start's load and add, never needed there, cost PoCL ~8 % of the preloaded trace). */
#define MV_TRACE_STARTS_IN_PARAMS 1u
#define MV_TRACE_STAMPS 2u
#define MV_TRACE_RELATIVE 4u

MV_STRUCT_BEGIN(MvTraceParams)
  mv_u32 first;     /* rays [first, first + count) in this dispatch */
  mv_u32 count;
  mv_u32 mode;      /* MV_TRACE_MODE: levels, ray source, output and page size */
  mv_u32 width;     /* camera rays: image width */
  mv_u32 max_steps; /* give up after this many loop steps (the same on every device) */
  mv_f32 proj;      /* LOD factor, see above; 0 = voxels only */
  mv_u32 block;     /* rays per work-item, contiguous (CPU devices: neighbouring rays share cache lines); 0 =
                       grid-stride */
  mv_u32 level_base[MV_TRACE_PARAM_LEVELS]; /* ssvdag: where level 3 + k starts in the inner stream; paged: see
                                               MV_TRACE_PAGE_STAMP */
MV_STRUCT_END(MvTraceParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvTraceParams, 80);
MV_LAYOUT_AT(MvTraceParams, first, 0); MV_LAYOUT_AT(MvTraceParams, count, 4); MV_LAYOUT_AT(MvTraceParams, mode, 8);
MV_LAYOUT_AT(MvTraceParams, width, 12); MV_LAYOUT_AT(MvTraceParams, max_steps, 16);
MV_LAYOUT_AT(MvTraceParams, proj, 20); MV_LAYOUT_AT(MvTraceParams, block, 24);
MV_LAYOUT_AT(MvTraceParams, level_base, 28);
#endif

MV_STRUCT_BEGIN(MvRay)
  mv_f32 ox; mv_f32 oy; mv_f32 oz;
  mv_f32 dx; mv_f32 dy; mv_f32 dz;
  mv_f32 tmax;
  mv_f32 lod_t; /* added to t in the LOD test: a secondary ray keeps the LOD of its primary */
MV_STRUCT_END(MvRay)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvRay, 4 * MV_RAY_FLOATS); /* the ray record: its fields in order */
MV_LAYOUT_AT(MvRay, ox, 0); MV_LAYOUT_AT(MvRay, oy, 4); MV_LAYOUT_AT(MvRay, oz, 8); MV_LAYOUT_AT(MvRay, dx, 12);
MV_LAYOUT_AT(MvRay, dy, 16); MV_LAYOUT_AT(MvRay, dz, 20); MV_LAYOUT_AT(MvRay, tmax, 24); MV_LAYOUT_AT(MvRay, lod_t, 28);
#endif

MV_STRUCT_BEGIN(MvHit)
  mv_f32 t;
  mv_u32 x; mv_u32 y; mv_u32 z; /* the cell at the hit level */
  mv_u32 info;
  mv_u32 steps;
MV_STRUCT_END(MvHit)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvHit, 4 * MV_HIT_WORDS); /* the hit record: its fields in order (t as float bits) */
MV_LAYOUT_AT(MvHit, t, 0); MV_LAYOUT_AT(MvHit, x, 4); MV_LAYOUT_AT(MvHit, y, 8); MV_LAYOUT_AT(MvHit, z, 12);
MV_LAYOUT_AT(MvHit, info, 16); MV_LAYOUT_AT(MvHit, steps, 20);
#endif

/* The hit record of a ray that meets nothing. */
MV_INLINE MvHit mv_miss_hit() {
  MvHit h;
  h.t = 0.0f;
  h.x = 0u; h.y = 0u; h.z = 0u;
  h.info = MV_TRACE_MISS | (MV_AXIS_NONE << 2);
  h.steps = 0u;
  return h;
}

/* Ray i of a ray buffer (MV_RAY_FLOATS per ray, MvRay's fields in order), read and written. */
MV_INLINE MvRay mv_load_ray(MvBufF32 rays, mv_u32 i) {
  MvRay r;
  mv_u32 b = MV_RAY_FLOATS * i;
  r.ox = MV_LD(rays, b); r.oy = MV_LD(rays, b + 1u); r.oz = MV_LD(rays, b + 2u);
  r.dx = MV_LD(rays, b + 3u); r.dy = MV_LD(rays, b + 4u); r.dz = MV_LD(rays, b + 5u);
  r.tmax = MV_LD(rays, b + 6u);
  r.lod_t = MV_LD(rays, b + 7u);
  return r;
}

MV_INLINE void mv_store_ray(MvBufU32 dst, mv_u32 i, MvRay r) {
  mv_u32 b = MV_RAY_FLOATS * i;
  MV_ST(dst, b, MV_FBITS(r.ox)); MV_ST(dst, b + 1u, MV_FBITS(r.oy)); MV_ST(dst, b + 2u, MV_FBITS(r.oz));
  MV_ST(dst, b + 3u, MV_FBITS(r.dx)); MV_ST(dst, b + 4u, MV_FBITS(r.dy)); MV_ST(dst, b + 5u, MV_FBITS(r.dz));
  MV_ST(dst, b + 6u, MV_FBITS(r.tmax));
  MV_ST(dst, b + 7u, MV_FBITS(r.lod_t));
}

/* Hit record i of a result buffer (MV_HIT_WORDS per ray, MvHit's fields in order, t as its bits), written and
 * read. */
MV_INLINE void mv_store_hit(MvBufU32 hits, mv_u32 i, MvHit h) {
  mv_u32 b = MV_HIT_WORDS * i;
  MV_ST(hits, b, MV_FBITS(h.t));
  MV_ST(hits, b + 1u, h.x);
  MV_ST(hits, b + 2u, h.y);
  MV_ST(hits, b + 3u, h.z);
  MV_ST(hits, b + 4u, h.info);
  MV_ST(hits, b + 5u, h.steps);
}

MV_INLINE MvHit mv_load_hit(MvBufConstU32 hits, mv_u32 i) {
  MvHit h;
  mv_u32 b = MV_HIT_WORDS * i;
  h.t = MV_BITSF(MV_LD(hits, b));
  h.x = MV_LD(hits, b + 1u); h.y = MV_LD(hits, b + 2u); h.z = MV_LD(hits, b + 3u);
  h.info = MV_LD(hits, b + 4u);
  h.steps = MV_LD(hits, b + 5u);
  return h;
}

/* The frame's pixel of camera ray `ray` (MV_CAMERA_FIRST on). */
MV_INLINE mv_u32 mv_camera_pixel(MvBufF32 cam, mv_u32 ray) { return ray + MV_FBITS(MV_LD(cam, MV_CAMERA_FIRST)); }

/* The camera ray of ray `ray`, pixel mv_camera_pixel (row 0 at the top): camera buffer = eye[3], base[3],
 * du[3], dv[3], tmax, first (the MV_CAMERA_* offsets), where the direction is base + x du + y dv (not
 * normalized: its component along the view axis is 1, so t is depth along the view axis). */
MV_INLINE MvRay mv_camera_ray(MvBufF32 cam, mv_u32 ray, mv_u32 width) {
  MvRay r;
  mv_u32 pixel = mv_camera_pixel(cam, ray);
  mv_f32 fx = MV_F32(pixel % width), fy = MV_F32(pixel / width);
  r.ox = MV_LD(cam, MV_CAMERA_EYE); r.oy = MV_LD(cam, MV_CAMERA_EYE + 1u); r.oz = MV_LD(cam, MV_CAMERA_EYE + 2u);
  MV_PRECISE mv_f32 dx = MV_LD(cam, MV_CAMERA_BASE) + fx * MV_LD(cam, MV_CAMERA_DU) + fy * MV_LD(cam, MV_CAMERA_DV);
  MV_PRECISE mv_f32 dy =
      MV_LD(cam, MV_CAMERA_BASE + 1u) + fx * MV_LD(cam, MV_CAMERA_DU + 1u) + fy * MV_LD(cam, MV_CAMERA_DV + 1u);
  MV_PRECISE mv_f32 dz =
      MV_LD(cam, MV_CAMERA_BASE + 2u) + fx * MV_LD(cam, MV_CAMERA_DU + 2u) + fy * MV_LD(cam, MV_CAMERA_DV + 2u);
  r.dx = dx; r.dy = dy; r.dz = dz;
  r.tmax = MV_LD(cam, MV_CAMERA_TMAX);
  r.lod_t = 0.0f;
  return r;
}

MV_INLINE MvRay mv_trace_source_ray(MvBufF32 rays, MvBufF32 cam, mv_u32 i, MvTraceParams p) {
  return MV_TRACE_CAMERA(p) == 1u ? mv_camera_ray(cam, i, p.width) : mv_load_ray(rays, i);
}

#endif /* MV_TRACE_TYPES_H */
