// Vulkan entry point of the surface voxelizer (body: common/voxelize.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/voxelize.h"

#if defined(MV_ENTRY_mesh_voxel_keys)
MV_ARGS(MvBufU64 bkeys; MvBufU64 bmeta; MvBufU64 voxel_keys; MvBufU32 voxel_brick; MvVoxelizeParams p;);

void main() {
  mv_mesh_voxel_keys(args.bkeys, args.bmeta, args.voxel_keys, args.voxel_brick, args.p, MV_GLOBAL_ID(),
                     MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_mesh_voxel_best_colours)
MV_ARGS(MvBufF32 tris; MvBufF64 terms; MvBufU64 fmasks; MvBufU32 ftris; MvBufU32 run_starts; MvBufU64 voxel_keys;
        MvBufU32 voxel_brick; MvBufU32 attr; MvBufU32 texels; MvBufU32 best; MvBufU32 voxel_rgb; MvVoxelizeParams p;);

void main() {
  mv_mesh_voxel_best_colours(args.tris, args.terms, args.fmasks, args.ftris, args.run_starts, args.voxel_keys,
                             args.voxel_brick, args.attr, args.texels, args.best, args.voxel_rgb, args.p,
                             MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_mesh_voxel_colours)
layout(push_constant) uniform Args {
  MvBufF32 tris; MvBufF64 terms; MvBufU32 attr; MvBufU32 texels; MvBufU32 best; MvBufU64 voxel_keys;
  MvBufU32 voxel_rgb; MvVoxelizeParams p;
} args;

void main() {
  mv_mesh_voxel_colours(args.tris, args.terms, args.attr, args.texels, args.best, args.voxel_keys, args.voxel_rgb,
                        args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_mesh_best_fragments)
MV_ARGS(MvBufF32 tris; MvBufF64 terms; MvBufU64 fkeys; MvBufU64 fmasks; MvBufU32 ftris; MvBufU64 bkeys; MvBufU64 bmeta;
        MvBufU32 best; MvBufU32 seen; MvVoxelizeParams p;);

void main() {
  mv_mesh_best_fragments(args.tris, args.terms, args.fkeys, args.fmasks, args.ftris, args.bkeys, args.bmeta, args.best,
                         args.seen, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_mesh_triangle_terms)
layout(push_constant) uniform Args { MvBufF32 tris; MvBufF64 terms; MvVoxelizeParams p; } args;

void main() { mv_mesh_triangle_terms(args.tris, args.terms, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#else
layout(push_constant) uniform Args {
  MvBufF32 tris; MvBufU32 item_tri; MvBufU32 item_col; MvBufU32 counter; MvBufU64 keys; MvBufU64 masks;
  MvBufU32 slot_tris; MvVoxelizeParams p;
} args;

void main() {
  for (uint j = MV_GLOBAL_ID(); j < args.p.items; j += MV_GLOBAL_SIZE()) {
    uint i = args.p.first_item + j;
    mv_voxelize_item(args.tris, args.counter, args.keys, args.masks, args.slot_tris, MV_LD(args.item_tri, i),
                     MV_LD(args.item_col, i), args.p);
  }
}
#endif
