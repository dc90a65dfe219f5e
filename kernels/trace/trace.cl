// OpenCL entry points of ray traversal (bodies: common/trace.h, common/secondary.h).
#include "common/secondary.h"
#include "common/trace_beam.h"
#include "common/trace_colour_paged.h"

// One kernel per encoding family, the encoding a constant: svo / svdag / ussvdag (32-bit words) and ssvdag
// (level starts read from memory, or taken from the parameters: mv_level_base).
__kernel void trace_rays(__global float* rays, __global float* cam, __global uint* words, __global uint* bricks,
                         __global uint* lvl_off, __global uint* out, MvTraceParams p) {
  mv_trace_rays(rays, cam, words, bricks, lvl_off, words, words, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_SVDAG, 0u);
}

__kernel void trace_rays_ssvdag(__global float* rays, __global float* cam, __global uint* words,
                                __global uint* bricks, __global uint* lvl_off, __global uint* out, MvTraceParams p) {
  mv_trace_rays(rays, cam, words, bricks, lvl_off, words, words, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_SSVDAG, 0u);
}

__kernel void trace_rays_ssvdag_params(__global float* rays, __global float* cam, __global uint* words,
                                       __global uint* bricks, __global uint* lvl_off, __global uint* out,
                                       MvTraceParams p) {
  mv_trace_rays(rays, cam, words, bricks, lvl_off, words, words, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_SSVDAG,
                MV_TRACE_STARTS_IN_PARAMS);
}

// 32-bit word encodings through the page cache: slots, page table, usage and request stamps (mv_page_resolve);
// the rays come from `src`, the ray buffer or (p.camera) the camera record. Each stamps the slots it reads for
// the LRU; the _whole kernels do not (a preloaded cache with a slot for every page: mv_trace_rays).
__kernel void trace_rays_paged(__global float* src, __global uint* slots, __global uint* table, __global uint* usage,
                               __global uint* request, __global uint* out, MvTraceParams p) {
  mv_trace_rays(src, src, slots, table, table, usage, request, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_PAGED,
                MV_TRACE_STAMPS);
}

__kernel void trace_rays_paged_whole(__global float* src, __global uint* slots, __global uint* table,
                                     __global uint* usage, __global uint* request, __global uint* out, MvTraceParams p) {
  mv_trace_rays(src, src, slots, table, table, usage, request, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_PAGED,
                0u);
}

// The same for a stream whose pointers count from their level's start (level order: its starts follow the
// page table).
__kernel void trace_rays_paged_relative(__global float* src, __global uint* slots, __global uint* table,
                                        __global uint* usage, __global uint* request, __global uint* out,
                                        MvTraceParams p) {
  mv_trace_rays(src, src, slots, table, table, usage, request, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_PAGED,
                MV_TRACE_STAMPS | MV_TRACE_RELATIVE);
}

__kernel void trace_rays_paged_whole_relative(__global float* src, __global uint* slots, __global uint* table,
                                              __global uint* usage, __global uint* request, __global uint* out,
                                              MvTraceParams p) {
  mv_trace_rays(src, src, slots, table, table, usage, request, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_PAGED,
                MV_TRACE_RELATIVE);
}

// The same for an ssvdag through the page cache (its level starts follow the page table), and the _params
// kernels that take them from the parameters instead (mv_params_level_base).
__kernel void trace_rays_paged_ssvdag(__global float* src, __global uint* slots, __global uint* table,
                                      __global uint* usage, __global uint* request, __global uint* out, MvTraceParams p) {
  mv_trace_rays(src, src, slots, table, table, usage, request, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(),
                MV_ENC_PAGED_SSVDAG, MV_TRACE_STAMPS);
}

__kernel void trace_rays_paged_ssvdag_params(__global float* src, __global uint* slots, __global uint* table,
                                             __global uint* usage, __global uint* request, __global uint* out,
                                             MvTraceParams p) {
  mv_trace_rays(src, src, slots, table, table, usage, request, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(),
                MV_ENC_PAGED_SSVDAG, MV_TRACE_STAMPS | MV_TRACE_STARTS_IN_PARAMS);
}

__kernel void trace_rays_paged_ssvdag_whole(__global float* src, __global uint* slots, __global uint* table,
                                            __global uint* usage, __global uint* request, __global uint* out,
                                            MvTraceParams p) {
  mv_trace_rays(src, src, slots, table, table, usage, request, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(),
                MV_ENC_PAGED_SSVDAG, 0u);
}

__kernel void trace_rays_paged_ssvdag_whole_params(__global float* src, __global uint* slots, __global uint* table,
                                                   __global uint* usage, __global uint* request, __global uint* out,
                                                   MvTraceParams p) {
  mv_trace_rays(src, src, slots, table, table, usage, request, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(),
                MV_ENC_PAGED_SSVDAG, MV_TRACE_STARTS_IN_PARAMS);
}

__kernel void secondary_flags(__global uint* hits, __global uint* flags, MvSecondaryParams p) {
  mv_secondary_flags(hits, flags, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void secondary_rays(__global float* rays, __global float* cam, __global uint* hits, __global uint* listed,
                             __global float* table, __global uint* out, MvSecondaryParams p) {
  mv_secondary_rays(rays, cam, hits, listed, table, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

// The beam pre-pass (common/trace_beam.h): the coarse grid's full cells from one trace count each, the grid
// dilated, and each tile's start after the camera record.
__kernel void beam_pack(__global uint* counts, __global uint* full, MvBeamParams p) {
  mv_beam_pack(counts, full, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void beam_dilate(__global uint* full, __global uint* marked, MvBeamParams p) {
  mv_beam_dilate(full, marked, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void beam_starts(__global uint* marked, __global uint* cam, MvBeamParams p) {
  mv_beam_starts(marked, cam, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

// Each hit's colour from the depth-first colours (common/trace_colour.h): the 32-bit word encodings, and ssvdag.
__kernel void hit_colours(__global uint* hits, __global uint* words, __global uint* bricks, __global uint* meta,
                          __global uint* colours, __global uint* out, MvTraceParams p) {
  mv_hit_colours(hits, words, bricks, meta, colours, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_SVDAG);
}

__kernel void hit_colours_ssvdag(__global uint* hits, __global uint* words, __global uint* bricks, __global uint* meta,
                                 __global uint* colours, __global uint* out, MvTraceParams p) {
  mv_hit_colours(hits, words, bricks, meta, colours, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_SSVDAG);
}

// Each hit's depth-first colour entry through the page cache (common/trace_colour_paged.h): the slots, the page
// table and the size plane; a word stream, and an ssvdag.
__kernel void hit_entries_paged(__global uint* hits, __global uint* slots, __global uint* table, __global uint* plane,
                                __global uint* out, MvTraceParams p) {
  mv_paged_hit_entries(hits, slots, table, plane, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_PAGED);
}

__kernel void hit_entries_paged_ssvdag(__global uint* hits, __global uint* slots, __global uint* table,
                                       __global uint* plane, __global uint* out, MvTraceParams p) {
  mv_paged_hit_entries(hits, slots, table, plane, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_ENC_PAGED_SSVDAG);
}
