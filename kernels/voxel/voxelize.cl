// OpenCL entry point of the surface voxelizer (body: common/voxelize.h). One kernel, two modes (p.emit).
#include "common/voxelize.h"

__kernel void voxelize(__global float* tris, __global uint* item_tri, __global uint* item_col,
                       __global uint* counts, __global ulong* keys, MvVoxelizeParams p) {
  for (uint j = MV_GLOBAL_ID(); j < p.items; j += MV_GLOBAL_SIZE()) {
    uint i = p.first_item + j;
    uint at = p.emit != 0u ? counts[i] : 0u;
    uint found = mv_voxelize_item(tris, keys, at, item_tri[i], item_col[i], p);
    if (p.emit == 0u) counts[i] = found;
  }
}
