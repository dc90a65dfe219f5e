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

// Mesh colours (common/mesh_colour.h): the voxels' best fragments in the long runs of the voxelizer's sorted
// fragments, a window of them a work-item.
__kernel void mesh_best_fragments(__global float* tris, __global double* terms, __global ulong* fkeys,
                                  __global ulong* fmasks, __global uint* ftris, __global ulong* bkeys,
                                  __global ulong* bmeta, __global uint* best, __global uint* seen, MvVoxelizeParams p) {
  mv_mesh_best_fragments(tris, terms, fkeys, fmasks, ftris, bkeys, bmeta, best, seen, p, MV_GLOBAL_ID(),
                         MV_GLOBAL_SIZE());
}

// What every nearest point on a triangle shares, a work-item per triangle of the batch.
__kernel void mesh_triangle_terms(__global float* tris, __global double* terms, MvVoxelizeParams p) {
  mv_mesh_triangle_terms(tris, terms, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

// Each voxel's key and brick, a work-item per brick; a voxel's best fragment and colour where its brick's run is
// short; then each voxel's colour where its best fragment's triangle is in this batch.
__kernel void mesh_voxel_keys(__global ulong* bkeys, __global ulong* bmeta, __global ulong* voxel_keys,
                              __global uint* voxel_brick, MvVoxelizeParams p) {
  mv_mesh_voxel_keys(bkeys, bmeta, voxel_keys, voxel_brick, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void mesh_voxel_best_colours(__global float* tris, __global double* terms, __global ulong* fmasks,
                                      __global uint* ftris, __global uint* run_starts, __global ulong* voxel_keys,
                                      __global uint* voxel_brick, __global uint* attr, __global uint* texels,
                                      __global uint* best, __global uint* voxel_rgb, MvVoxelizeParams p) {
  mv_mesh_voxel_best_colours(tris, terms, fmasks, ftris, run_starts, voxel_keys, voxel_brick, attr, texels, best,
                             voxel_rgb, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void mesh_voxel_colours(__global float* tris, __global double* terms, __global uint* attr,
                                 __global uint* texels, __global uint* best, __global ulong* voxel_keys,
                                 __global uint* voxel_rgb, MvVoxelizeParams p) {
  mv_mesh_voxel_colours(tris, terms, attr, texels, best, voxel_keys, voxel_rgb, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
