// OpenCL entry point of the surface voxelizer (body: common/voxelize.h).
#include "common/voxelize.h"

__kernel void voxelize(__global float* tris, __global uint* item_tri, __global uint* item_col,
                       __global uint* counter, __global ulong* keys, __global ulong* masks, MvVoxelizeParams p) {
  for (uint j = MV_GLOBAL_ID(); j < p.items; j += MV_GLOBAL_SIZE()) {
    uint i = p.first_item + j;
    mv_voxelize_item(tris, counter, keys, masks, item_tri[i], item_col[i], p, 0u);
  }
}

// Mesh colours (common/mesh_colour.h): the same walk, each brick updating its voxels' best fragments; `bkeys`,
// `bmeta` and `best` in the places of the voxelizer's keys, masks and counter.
__kernel void mesh_colour_walk(__global float* tris, __global uint* item_tri, __global uint* item_col,
                               __global uint* best, __global ulong* bkeys, __global ulong* bmeta, MvVoxelizeParams p) {
  for (uint j = MV_GLOBAL_ID(); j < p.items; j += MV_GLOBAL_SIZE()) {
    uint i = p.first_item + j;
    mv_voxelize_item(tris, best, bkeys, bmeta, item_tri[i], item_col[i], p, 1u);
  }
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
