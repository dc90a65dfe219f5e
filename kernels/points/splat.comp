// Vulkan entry points of the point splats, one module per -DMV_ENTRY_<name> (bodies: common/splat.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/splat.h"

layout(push_constant) uniform Args { MvBufU32 xyz; MvBufU32 depth; MvBufU32 index_; MvSplatParams p; } args;
#if defined(MV_ENTRY_splat_depth)
void main() { mv_splat(args.xyz, args.depth, args.index_, args.p, false, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_splat_index)
void main() { mv_splat(args.xyz, args.depth, args.index_, args.p, true, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#else
#error "define MV_ENTRY_splat_depth or MV_ENTRY_splat_index"
#endif
