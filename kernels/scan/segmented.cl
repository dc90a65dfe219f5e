// OpenCL entry points of the segmented operations (bodies: common/segmented.h).
#include "common/segmented.h"

__kernel void seg_heads(__global ulong* keys, __global uint* heads, MvSegParams p) {
  mv_seg_heads(keys, heads, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void seg_starts(__global uint* e, __global uint* starts, MvSegParams p) {
  mv_seg_starts(e, starts, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void seg_sum(__global ulong* prefix, __global uint* starts, __global ulong* sums, MvSegParams p) {
  mv_seg_sum(prefix, starts, sums, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void seg_scan(__global ulong* prefix, __global uint* e, __global uint* starts, __global ulong* out,
                       MvSegParams p) {
  mv_seg_scan(prefix, e, starts, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void seg_argmin_reduce(__global ulong* values, __global uint* e, __global ulong* agg, MvSegParams p) {
  uint b = MV_GLOBAL_ID();
  if (b < p.blocks) mv_seg_argmin_reduce(values, e, agg, p, b);
}

__kernel void seg_argmin_small(__global ulong* agg, MvSegParams p) {
  if (MV_GLOBAL_ID() == 0u) mv_seg_argmin_small(agg, p);
}

__kernel void seg_argmin_apply(__global ulong* values, __global uint* e, __global ulong* agg, __global uint* out,
                               MvSegParams p) {
  uint b = MV_GLOBAL_ID();
  if (b < p.blocks) mv_seg_argmin_apply(values, e, agg, out, p, b);
}
