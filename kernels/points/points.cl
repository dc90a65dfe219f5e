// OpenCL entry points of the point-cloud LOD kernels (bodies: common/points.h).
#include "common/points.h"

__kernel void point_codes(__global uint* xyz, __global ulong* keys, __global uint* index, MvPointParams p) {
  mv_point_codes(xyz, keys, index, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void rep_count(__global ulong* codes, __global uint* bounds, __global uint* cells, __global uint* kept,
                        MvPointParams p) {
  mv_rep_count(codes, bounds, cells, kept, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void rep_select(__global ulong* codes, __global uint* bounds, __global uint* cells, __global uint* offsets,
                         __global uint* out, MvPointParams p) {
  mv_rep_select(codes, bounds, cells, offsets, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
