// OpenCL entry point of the surface voxelizer (body: common/voxelize.h).
#include "common/voxelize.h"

__kernel void voxelize(__global float* tris, __global uint* item_tri, __global uint* item_col,
                       __global uint* counter, __global ulong* keys, __global ulong* masks, MvVoxelizeParams p) {
  for (uint j = MV_GLOBAL_ID(); j < p.items; j += MV_GLOBAL_SIZE()) {
    uint i = p.first_item + j;
    mv_voxelize_item(tris, counter, keys, masks, item_tri[i], item_col[i], p);
  }
}
