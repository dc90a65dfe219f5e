// Vulkan entry points of the point-cloud kernels, one module per -DMV_ENTRY_<name> (bodies: common/points.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/points.h"

#if defined(MV_ENTRY_point_codes)
layout(push_constant) uniform Args { MvBufU32 xyz; MvBufU64 keys; MvBufU32 index_; MvPointParams p; } args;
void main() { mv_point_codes(args.xyz, args.keys, args.index_, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_point_bounds)
layout(push_constant) uniform Args { MvBufU32 xyz; MvBufU32 partial; MvPointParams p; } args;
void main() { mv_point_bounds(args.xyz, args.partial, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#else
#error "define MV_ENTRY_point_codes or MV_ENTRY_point_bounds"
#endif
