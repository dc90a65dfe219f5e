// OpenCL entry point of the surface voxelizer (body: common/voxelize.h).
#include "common/voxelize.h"

__kernel void voxelize(__global float* tris, __global uint* item_tri, __global uint* item_col,
                       __global uint* counter, __global ulong* keys, __global ulong* masks, __global uint* slot_tris,
                       MvVoxelizeParams p) {
  for (uint j = MV_GLOBAL_ID(); j < p.items; j += MV_GLOBAL_SIZE()) {
    uint i = p.first_item + j;
    mv_voxelize_item(tris, counter, keys, masks, slot_tris, item_tri[i], item_col[i], p);
  }
}

// Mesh colours (common/mesh_colour.h): the voxels' best fragments, from the voxelizer's sorted fragments.
__kernel void mesh_best_fragments(__global float* tris, __global ulong* fkeys, __global ulong* fmasks,
                                  __global uint* ftris, __global ulong* bkeys, __global ulong* bmeta,
                                  __global uint* best, MvVoxelizeParams p) {
  mv_mesh_best_fragments(tris, fkeys, fmasks, ftris, bkeys, bmeta, best, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

// Each voxel's key, a work-item per brick; then each voxel's colour where its best fragment's triangle is in this
// batch (common/mesh_colour.h).
__kernel void mesh_voxel_keys(__global ulong* bkeys, __global ulong* bmeta, __global ulong* voxel_keys, MvVoxelizeParams p) {
  mv_mesh_voxel_keys(bkeys, bmeta, voxel_keys, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void mesh_voxel_colours(__global float* tris, __global uint* attr, __global uint* texels, __global uint* best,
                                 __global ulong* voxel_keys, __global uint* voxel_rgb, MvVoxelizeParams p) {
  mv_mesh_voxel_colours(tris, attr, texels, best, voxel_keys, voxel_rgb, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
