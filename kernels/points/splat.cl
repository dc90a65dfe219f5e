// OpenCL entry points of the point splats (bodies: common/splat.h).
#include "common/splat.h"

__kernel void splat_depth(__global uint* xyz, __global uint* depth, __global uint* index, MvSplatParams p) {
  mv_splat(xyz, depth, index, p, false, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void splat_index(__global uint* xyz, __global uint* depth, __global uint* index, MvSplatParams p) {
  mv_splat(xyz, depth, index, p, true, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
