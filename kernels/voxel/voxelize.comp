// Vulkan entry point of the surface voxelizer (body: common/voxelize.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/voxelize.h"

layout(push_constant) uniform Args {
  MvBufF32 tris; MvBufU32 item_tri; MvBufU32 item_col; MvBufU32 counter; MvBufU64 keys; MvBufU64 masks;
  MvVoxelizeParams p;
} args;

void main() {
  for (uint j = MV_GLOBAL_ID(); j < args.p.items; j += MV_GLOBAL_SIZE()) {
    uint i = args.p.first_item + j;
    mv_voxelize_item(args.tris, args.counter, args.keys, args.masks, MV_LD(args.item_tri, i), MV_LD(args.item_col, i),
                     args.p);
  }
}
