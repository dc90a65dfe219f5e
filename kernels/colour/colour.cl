// OpenCL entry points of the voxel colour kernels (bodies: common/colour.h).
#include "common/colour.h"

__kernel void colour_unpack(__global uint* rgb, __global uint* planes, MvColourParams p) {
  mv_colour_unpack(rgb, planes, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_level(__global ulong* sums, __global uint* rgb, __global uint* planes, MvColourParams p) {
  mv_colour_level(sums, rgb, planes, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_parent_keys(__global ulong* keys, __global uint* starts, __global ulong* up, MvColourParams p) {
  mv_colour_parent_keys(keys, starts, up, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_child_sums(__global uint* planes, __global uint* starts, __global ulong* sums, MvColourParams p) {
  mv_colour_child_sums(planes, starts, sums, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_place(__global uint* e, __global uint* starts, __global uint* sizes, __global uint* parent_index,
                           __global uint* rgb, __global uint* index, __global uint* attributes, MvColourParams p) {
  mv_colour_place(e, starts, sizes, parent_index, rgb, index, attributes, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
