// OpenCL entry points of GrabCut's per-pixel work (bodies: common/grabcut.h, sums: common/grabcut_sums.h).
#include "common/grabcut_sums.h"

__kernel void grabcut_colours(__global uint* samples, __global uint* colour, MvGrabCutParams p) {
  for (uint i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) mv_gc_colours(samples, colour, p, i);
}

__kernel void grabcut_edges(__global double* weights, __global double* c, __global uint* edges, MvGrabCutParams p) {
  for (uint i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) mv_gc_edges(weights, c, edges, p, i);
}

__kernel void grabcut_terminals(__global double* terms, __global double* c, __global uint* q, MvGrabCutParams p) {
  for (uint i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) mv_gc_terminals(terms, c, q, p, i);
}

__kernel void grabcut_seed_d2(__global uint* colour, __global uint* labels, __global uint* d2_bg,
                              __global uint* d2_fg, MvGrabCutParams p) {
  for (uint i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) mv_gc_seed_d2(colour, labels, d2_bg, d2_fg, p, i);
}

__kernel void grabcut_seed_find(__global ulong* scan_bg, __global ulong* scan_fg, __global uint* found,
                                MvGrabCutParams p) {
  for (uint i = MV_GLOBAL_ID(); i < p.pixels; i += MV_GLOBAL_SIZE()) mv_gc_seed_find(scan_bg, scan_fg, found, p, i);
}

__kernel void grabcut_beta_sum(__global uint* colour, __global uint* sums, MvGrabCutParams p) {
  MV_SHARED(uint, acc, 2);
  mv_gc_beta_sum(acc, colour, sums, p);
}

__kernel void grabcut_smooth_sum(__global uint* colour, __global double* c, __global double* weights,
                                 __global uint* sums, MvGrabCutParams p) {
  MV_SHARED(uint, acc, 2);
  mv_gc_smooth_sum(acc, colour, c, weights, sums, p);
}

__kernel void grabcut_data(__global uint* colour, __global uint* labels, __global uint* comp, __global double* c,
                           __global double* terms, __global uint* sums, MvGrabCutParams p) {
  MV_SHARED(uint, acc, 2);
  mv_gc_data(acc, colour, labels, comp, c, terms, sums, p);
}

__kernel void grabcut_moments(__global uint* colour, __global uint* labels, __global uint* comp, __global uint* sums,
                              MvGrabCutParams p) {
  MV_SHARED(uint, acc, 200);
  mv_gc_moments(acc, colour, labels, comp, sums, p);
}

__kernel void grabcut_kmeans(__global uint* colour, __global uint* labels, __global uint* comp, __global double* c,
                             __global uint* sums, MvGrabCutParams p) {
  MV_SHARED(uint, acc, 80);
  mv_gc_kmeans(acc, colour, labels, comp, c, sums, p);
}

__kernel void grabcut_labels(__global uint* source_side, __global uint* labels, __global uint* sums,
                             MvGrabCutParams p) {
  MV_SHARED(uint, acc, 2);
  mv_gc_labels(acc, source_side, labels, sums, p);
}
