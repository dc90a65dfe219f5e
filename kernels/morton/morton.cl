// OpenCL entry points of Morton encoding (bodies: common/morton.h).
#include "common/morton.h"

__kernel void morton_encode64(__global uint* xyz, __global ulong* keys, MvMortonParams p) {
  mv_morton_encode64(xyz, keys, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void morton_encode32(__global uint* xyz, __global uint* keys, MvMortonParams p) {
  mv_morton_encode32(xyz, keys, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
