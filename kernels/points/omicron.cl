// OpenCL entry points of the OMiCroN builder's representative kernels (bodies: common/omicron.h).
#include "common/omicron.h"

__kernel void omicron_rep_heads(__global uint* bounds, __global uint* heads, MvRepParams p) {
  mv_omicron_rep_heads(bounds, heads, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void omicron_rep_distance(__global ulong* codes, __global ulong* dist, MvRepParams p) {
  mv_omicron_rep_distance(codes, dist, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void omicron_rep_keep(__global uint* bounds, __global uint* e, __global uint* starts, __global uint* keep,
                               MvRepParams p) {
  mv_omicron_rep_keep(bounds, e, starts, keep, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void omicron_rep_compact(__global uint* keep, __global uint* pos, __global uint* nearest, __global uint* dst,
                                  MvRepParams p) {
  mv_omicron_rep_compact(keep, pos, nearest, dst, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void omicron_rep_offsets(__global uint* bounds, __global uint* e, __global uint* pos, __global uint* offsets,
                                  MvRepParams p) {
  mv_omicron_rep_offsets(bounds, e, pos, offsets, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
