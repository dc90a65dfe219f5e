// OpenCL entry points of unique over sorted keys (bodies: common/unique.h).
#include "common/unique.h"

__kernel void unique_flags(__global ulong* keys, __global uint* flags, MvUniqueParams p) {
  mv_unique_flags(keys, flags, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void unique_compact(__global ulong* keys, __global uint* pos, __global ulong* out, MvUniqueParams p) {
  mv_unique_compact(keys, pos, out, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
