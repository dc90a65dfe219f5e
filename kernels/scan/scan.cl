// OpenCL entry points of the exclusive scan (bodies: common/scan.h).
#include "common/scan.h"

__kernel void scan_reduce(__global uint* in, __global ulong* sums, MvScanParams p) {
  uint b = MV_GLOBAL_ID();
  if (b < p.blocks) mv_scan_reduce(in, sums, p, b);
}

__kernel void scan_small(__global ulong* data, MvScanParams p) {
  if (MV_GLOBAL_ID() == 0u) mv_scan_small(data, p);
}

__kernel void scan_apply(__global uint* in, __global uint* out, __global ulong* sums, MvScanParams p) {
  uint b = MV_GLOBAL_ID();
  if (b < p.blocks) mv_scan_apply(in, out, sums, p, b);
}
