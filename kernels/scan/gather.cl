// OpenCL entry point of the record gather (body: common/gather.h).
#include "common/gather.h"

__kernel void gather_records(__global const uint* src, __global const uint* index, __global uint* dst,
                             MvGatherParams p) {
  mv_gather_records(src, index, dst, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
