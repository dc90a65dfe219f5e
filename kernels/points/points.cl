// OpenCL entry points of the point-cloud kernels (bodies: common/points.h).
#include "common/points.h"

__kernel void point_codes(__global uint* xyz, __global ulong* keys, __global uint* index, MvPointParams p) {
  mv_point_codes(xyz, keys, index, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void point_bounds(__global uint* xyz, __global uint* partial, MvPointParams p) {
  mv_point_bounds(xyz, partial, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
