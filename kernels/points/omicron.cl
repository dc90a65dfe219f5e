// OpenCL entry points of the OMiCroN builder's representative kernels (bodies: common/omicron.h).
#include "common/omicron.h"

__kernel void omicron_rep_count(__global ulong* codes, __global uint* bounds, __global uint* cells,
                                __global uint* kept, MvPointParams p) {
  mv_omicron_rep_count(codes, bounds, cells, kept, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void omicron_rep_select(__global ulong* codes, __global uint* bounds, __global uint* cells,
                                 __global uint* offsets, __global uint* out, MvPointParams p) {
  mv_omicron_rep_select(codes, bounds, cells, offsets, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
