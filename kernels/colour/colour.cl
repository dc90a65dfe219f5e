// OpenCL entry points of the voxel colour kernels (bodies: common/colour.h, common/quantize.h).
#include "common/colour.h"
#include "common/quantize.h"

__kernel void colour_pack_keys(__global ulong* keys, __global uint* rgb, MvColourParams p) {
  mv_colour_pack_keys(keys, rgb, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_unpack(__global uint* rgb, __global uint* planes, MvColourParams p) {
  mv_colour_unpack(rgb, planes, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_level(__global ulong* keys, __global ulong* sums, __global uint* planes, MvColourParams p) {
  mv_colour_level(keys, sums, planes, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_parent_keys(__global ulong* keys, __global uint* starts, __global ulong* up, MvColourParams p) {
  mv_colour_parent_keys(keys, starts, up, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_starts(__global ulong* keys, __global uint* rgb, __global uint* planes, MvColourParams p) {
  mv_colour_starts(keys, rgb, planes, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_nodes(__global ulong* keys, __global uint* planes, __global uint* sums, __global uint* attributes,
                           MvColourParams p) {
  mv_colour_nodes(keys, planes, sums, attributes, p, 0u, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void colour_nodes_wide(__global ulong* keys, __global uint* planes, __global uint* sums,
                                __global uint* attributes, MvColourParams p) {
  mv_colour_nodes(keys, planes, sums, attributes, p, 1u, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void quantize_nearest(__global double* lab, __global double* centres, __global uint* order,
                               __global uint* cluster, __global uint* moved, MvQuantizeParams p) {
  mv_quantize_nearest(lab, centres, order, cluster, moved, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
