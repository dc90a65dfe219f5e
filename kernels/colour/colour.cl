// OpenCL entry points of the voxel colour kernels (bodies: common/colour.h).
#include "common/colour.h"

__kernel void colour_unpack(__global uint* rgb, __global uint* planes, MvColourParams p) {
  mv_colour_unpack(rgb, planes, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_level(__global ulong* sums, __global uint* rgb, MvColourParams p) {
  mv_colour_level(sums, rgb, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_parent_keys(__global ulong* keys, __global uint* starts, __global ulong* up, MvColourParams p) {
  mv_colour_parent_keys(keys, starts, up, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_parents(__global ulong* keys, __global uint* below_planes, __global uint* starts,
                             __global ulong* up, __global uint* rgb, __global uint* planes, __global uint* sizes,
                             MvColourParams p) {
  mv_colour_parents(keys, below_planes, starts, up, rgb, planes, sizes, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_place(__global uint* e, __global uint* starts, __global uint* sizes, __global uint* parent_index,
                           __global uint* rgb, __global uint* index, __global uint* attributes, MvColourParams p) {
  mv_colour_place(e, starts, sizes, parent_index, rgb, index, attributes, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
