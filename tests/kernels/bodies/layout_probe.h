/* Layout probes: each struct the host shares with kernels as a device sees it (mv_lang.h: layout contracts).
 *
 * The host fills word k of a struct with MV_PROBE_WORD(k) and passes it as a probe kernel's parameters (push
 * constants on Vulkan, a by-value argument on OpenCL). The probe writes every field back, in declaration
 * order, as one 32-bit word (floats as their bits): a field the device places at another offset reads another
 * word. The host runs the same probe on its own struct (tests/test_layout.cpp) and compares the words. Where
 * the language has sizeof and addresses (host, OpenCL C) it also writes the struct's size and each field's
 * offset; GLSL has neither, so there the values alone tell.
 *
 * Output words: 0 = fields written, 1 = sizeof (0 in GLSL), 2 + k = field k, 2 + MV_PROBE_FIELDS + k = field k's
 * byte offset (not written in GLSL). */
#ifndef MV_LAYOUT_PROBE_H
#define MV_LAYOUT_PROBE_H
#include "common/dag.h"
#include "common/radix_sort.h"
#include "common/scan.h"
#include "lang_probe.h"
#include "common/secondary.h"
#include "common/trace_beam.h"
#include "common/unique.h"
#include "common/page_cache.h"
#include "common/points.h"
#include "common/omicron.h"
#include "common/segmented.h"
#include "common/gather.h"
#include "common/grabcut.h"
#include "common/splat.h"
#include "common/min_cut.h"
#include "common/min_cut_regions.h"
#include "common/mask_post.h"
#include "common/voxelize.h"
#include "common/colour.h"
#include "common/quantize.h"

#define MV_PROBE_FIELDS 32u /* at most, per struct */
#define MV_PROBE_WORDS (2u + 2u * MV_PROBE_FIELDS)
/* Distinct words that are also normal floats near 1, so a float field carries them unchanged. */
#define MV_PROBE_WORD(k) (0x3f800000u + (k))

/* The fields of each shared struct in declaration order: X(conversion to a 32-bit word, field). */
#define MV_FIELDS_MORTON(X) X(MV_U32, n) X(MV_U32, pad0)
#define MV_FIELDS_RADIX(X)                                                                                             \
  X(MV_U32, n) X(MV_U32, blocks) X(MV_U32, block_size) X(MV_U32, shift) X(MV_U32, has_values) X(MV_U32, count)     \
  X(MV_U32, local_top) X(MV_U32, local_low) X(MV_U32, scratch_stride) X(MV_U32, bucket_first) X(MV_U32, bucket_end)
#define MV_FIELDS_SCAN(X) X(MV_U32, n) X(MV_U32, blocks) X(MV_U32, block_size) X(MV_U32, wide) X(MV_U32, start_lo) \
  X(MV_U32, start_hi)
#define MV_FIELDS_UNIQUE(X) X(MV_U32, n) X(MV_U32, pad0)
#define MV_FIELDS_CACHE(X) X(MV_U32, n) X(MV_U32, stamp) X(MV_U32, count) X(MV_U32, page_words) X(MV_U32, runs_at)
#define MV_FIELDS_MIN_CUT(X)                                                                                            \
  X(MV_U32, width) X(MV_U32, height) X(MV_U32, conn) X(MV_U32, tile) X(MV_U32, tiles_x) X(MV_U32, tiles_y)           \
  X(MV_U32, color) X(MV_U32, color_tiles_x) X(MV_U32, first_tile) X(MV_U32, sweeps) X(MV_U32, stamp_now)  \
  X(MV_U32, stamp_since) X(MV_U32, first_pass) X(MV_U32, flag_word)
#define MV_FIELDS_MIN_CUT_REGIONS(X)                                                                                         \
  X(MV_U32, width) X(MV_U32, height) X(MV_U32, conn) X(MV_U32, regions_x) X(MV_U32, regions_y) X(MV_U32, group)        \
  X(MV_U32, budget) X(MV_U32, walk)
#define MV_FIELDS_MASK_POST(X) X(MV_U32, width) X(MV_U32, height) X(MV_U32, radius) X(MV_U32, pad0)
#define MV_FIELDS_LANG(X) X(MV_U32, n) X(MV_U32, width) X(MV_U32, height) X(MV_U32, pad0)
#define MV_FIELDS_VOXELIZE(X)                                                                                          \
  X(MV_U32, first_item) X(MV_U32, items) X(MV_U32, grid) X(MV_U32, columns_per_item) X(MV_U32, capacity)                   \
  X(MV_U32, box_size) X(MV_U32, box_x) X(MV_U32, box_y) X(MV_U32, box_z) X(MV_U32, thin) X(MV_U32, colour_pass)        \
  X(MV_U32, bricks) X(MV_U32, tri_base) X(MV_U32, record_tris) X(MV_U32, batch_tris) X(MV_U32, split_runs)
#define MV_FIELDS_DAG(X) \
  X(MV_U32, n) X(MV_U32, leaf) X(MV_U32, seed_lo) X(MV_U32, seed_hi) X(MV_U32, block) X(MV_U32, hash_drop)
#define MV_FIELDS_TRACE(X)                                                                                             \
  X(MV_U32, first) X(MV_U32, count) X(MV_U32, mode) X(MV_U32, width) X(MV_U32, max_steps) X(MV_FBITS, proj)            \
  X(MV_U32, block) X(MV_U32, level_base[0]) X(MV_U32, level_base[1]) X(MV_U32, level_base[2])                          \
  X(MV_U32, level_base[3]) X(MV_U32, level_base[4]) X(MV_U32, level_base[5]) X(MV_U32, level_base[6])                  \
  X(MV_U32, level_base[7]) X(MV_U32, level_base[8]) X(MV_U32, level_base[9]) X(MV_U32, level_base[10])                 \
  X(MV_U32, level_base[11]) X(MV_U32, level_base[12])
#define MV_FIELDS_SECONDARY(X)                                                                                         \
  X(MV_U32, first) X(MV_U32, count) X(MV_U32, levels) X(MV_U32, camera) X(MV_U32, width) X(MV_U32, kind)               \
  X(MV_U32, sample_k) X(MV_U32, stride) X(MV_U32, mask) X(MV_FBITS, lx) X(MV_FBITS, ly) X(MV_FBITS, lz)                \
  X(MV_FBITS, tmax) X(MV_FBITS, lead) X(MV_U32, block) X(MV_U32, pad2)
#define MV_FIELDS_BEAM(X)                                                                                              \
  X(MV_U32, first) X(MV_U32, count) X(MV_U32, cells) X(MV_U32, width) X(MV_U32, height) X(MV_FBITS, reach)             \
  X(MV_FBITS, lod_limit) X(MV_U32, block) X(MV_U32, tile) X(MV_U32, at) X(MV_U32, parent_at) X(MV_U32, pad)
#define MV_FIELDS_RAY(X)                                                                                               \
  X(MV_FBITS, ox) X(MV_FBITS, oy) X(MV_FBITS, oz) X(MV_FBITS, dx) X(MV_FBITS, dy) X(MV_FBITS, dz)                      \
  X(MV_FBITS, tmax) X(MV_FBITS, lod_t)
#define MV_FIELDS_POINT(X)                                                                                             \
  X(MV_U32, n) X(MV_U32, shift) X(MV_U32, min_x) X(MV_U32, min_y) X(MV_U32, min_z) X(MV_U32, base) X(MV_U32, lshift)   \
  X(MV_U32, first)
#define MV_FIELDS_SPLAT(X)                                                                                             \
  X(MV_U32, n) X(MV_U32, base) X(MV_U32, width) X(MV_U32, height) X(MV_U32, radius) X(MV_U32, focal_q8)               \
  X(MV_U32, cx_q8) X(MV_U32, cy_q8) X(MV_U32, near_q14) X(MV_U32, depth_shift) X(MV_U32, eye_x) X(MV_U32, eye_y)        \
  X(MV_U32, eye_z) X(MV_U32, rot[0]) X(MV_U32, rot[1]) X(MV_U32, rot[2]) X(MV_U32, rot[3]) X(MV_U32, rot[4])           \
  X(MV_U32, rot[5]) X(MV_U32, rot[6]) X(MV_U32, rot[7]) X(MV_U32, rot[8])
#define MV_FIELDS_SEG(X)                                                                                               \
  X(MV_U32, n) X(MV_U32, count) X(MV_U32, blocks) X(MV_U32, block_size) X(MV_U32, shift) X(MV_U32, planes)
#define MV_FIELDS_REP(X)                                                                                               \
  X(MV_U32, n) X(MV_U32, cells) X(MV_U32, groups) X(MV_U32, cell_bits) X(MV_U32, cap) X(MV_U32, pad0)
#define MV_FIELDS_GATHER(X)                                                                                            \
  X(MV_U32, words) X(MV_U32, units) X(MV_U32, per_record) X(MV_U32, unit_shift) X(MV_U32, lo) X(MV_U32, count)        \
  X(MV_U32, merge) X(MV_U32, block)
#define MV_FIELDS_GRABCUT(X)                                                                                           \
  X(MV_U32, width) X(MV_U32, height) X(MV_U32, pixels) X(MV_U32, channels) X(MV_U32, max_value) X(MV_U32, mode)        \
  X(MV_U32, sum_at) X(MV_U32, centres_bg) X(MV_U32, centres_fg) X(MV_U32, seeding) X(MV_U32, colour_bg)                \
  X(MV_U32, colour_fg) X(MV_U32, pick_bg_lo) X(MV_U32, pick_bg_hi) X(MV_U32, pick_fg_lo) X(MV_U32, pick_fg_hi)
#define MV_FIELDS_COLOUR(X)                                                                                            \
  X(MV_U32, n) X(MV_U32, levels) X(MV_U32, shift) X(MV_U32, stride)
#define MV_FIELDS_QUANTIZE(X) X(MV_U32, n) X(MV_U32, centres) X(MV_U32, spare0) X(MV_U32, spare1)
#define MV_FIELDS_HIT(X) X(MV_FBITS, t) X(MV_U32, x) X(MV_U32, y) X(MV_U32, z) X(MV_U32, info) X(MV_U32, steps)

#define MV_PROBE_VALUE(word, f)                                                                                        \
  MV_ST(dst, 2u + k, word(p.f));                                                                                       \
  k += 1u;
#if defined(MV_GLSL)
#define MV_PROBE_OFFSETS(FIELDS) MV_ST(dst, 1u, 0u);
#else
#define MV_PROBE_OFFSET(word, f)                                                                                       \
  MV_ST(dst, 2u + MV_PROBE_FIELDS + k, MV_U32((char*)&p.f - (char*)&p));                                               \
  k += 1u;
#define MV_PROBE_OFFSETS(FIELDS)                                                                                       \
  MV_ST(dst, 1u, MV_U32(sizeof(p)));                                                                                   \
  k = 0u;                                                                                                              \
  FIELDS(MV_PROBE_OFFSET)
#endif

/* mv_probe_<name>(dst, p): the probe of struct T, whose fields FIELDS lists. */
#define MV_PROBE(name, T, FIELDS)                                                                                      \
  MV_INLINE void mv_probe_##name(MvBufU32 dst, T p) {                                                                  \
    mv_u32 k = 0u;                                                                                                     \
    FIELDS(MV_PROBE_VALUE)                                                                                             \
    MV_ST(dst, 0u, k);                                                                                                 \
    MV_PROBE_OFFSETS(FIELDS)                                                                                           \
  }

MV_PROBE(morton_params, MvMortonParams, MV_FIELDS_MORTON)
MV_PROBE(radix_params, MvRadixParams, MV_FIELDS_RADIX)
MV_PROBE(scan_params, MvScanParams, MV_FIELDS_SCAN)
MV_PROBE(unique_params, MvUniqueParams, MV_FIELDS_UNIQUE)
MV_PROBE(cache_params, MvCacheParams, MV_FIELDS_CACHE)
MV_PROBE(lang_params, MvLangParams, MV_FIELDS_LANG)
MV_PROBE(voxelize_params, MvVoxelizeParams, MV_FIELDS_VOXELIZE)
MV_PROBE(dag_params, MvDagParams, MV_FIELDS_DAG)
MV_PROBE(trace_params, MvTraceParams, MV_FIELDS_TRACE)
MV_PROBE(secondary_params, MvSecondaryParams, MV_FIELDS_SECONDARY)
MV_PROBE(beam_params, MvBeamParams, MV_FIELDS_BEAM)
MV_PROBE(ray, MvRay, MV_FIELDS_RAY)
MV_PROBE(hit, MvHit, MV_FIELDS_HIT)
MV_PROBE(point_params, MvPointParams, MV_FIELDS_POINT)
MV_PROBE(splat_params, MvSplatParams, MV_FIELDS_SPLAT)
MV_PROBE(min_cut_params, MvMinCutParams, MV_FIELDS_MIN_CUT)
MV_PROBE(min_cut_regions_params, MvMinCutRegionsParams, MV_FIELDS_MIN_CUT_REGIONS)
MV_PROBE(mask_post_params, MvMaskPostParams, MV_FIELDS_MASK_POST)
MV_PROBE(seg_params, MvSegParams, MV_FIELDS_SEG)
MV_PROBE(rep_params, MvRepParams, MV_FIELDS_REP)
MV_PROBE(grabcut_params, MvGrabCutParams, MV_FIELDS_GRABCUT)
MV_PROBE(gather_params, MvGatherParams, MV_FIELDS_GATHER)
MV_PROBE(colour_params, MvColourParams, MV_FIELDS_COLOUR)
MV_PROBE(quantize_params, MvQuantizeParams, MV_FIELDS_QUANTIZE)

#endif /* MV_LAYOUT_PROBE_H */
