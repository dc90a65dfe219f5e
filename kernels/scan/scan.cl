// OpenCL entry points of the exclusive scan (bodies: common/scan.h, common/scan_group.h).
#include "common/scan.h"
#include "common/scan_group.h"

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

__kernel void scan_reduce_group(__global uint* in, __global ulong* sums, MvScanParams p) {
  MV_SHARED(ulong, scan_part, MV_SCAN_GROUP);
  mv_scan_reduce_group(MV_SHARED_ARG(scan_part) in, sums, p, MV_GROUP_ID(), MV_LOCAL_ID(), MV_LOCAL_SIZE());
}
