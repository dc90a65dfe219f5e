// Vulkan entry points of Morton encoding: -DMV_KEY64 selects 64-bit keys (bodies: common/morton.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/morton.h"

#ifdef MV_KEY64
layout(push_constant) uniform Args { MvBufU32 xyz; MvBufU64 keys; MvMortonParams p; } args;
void main() { mv_morton_encode64(args.xyz, args.keys, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#else
layout(push_constant) uniform Args { MvBufU32 xyz; MvBufU32 keys; MvMortonParams p; } args;
void main() { mv_morton_encode32(args.xyz, args.keys, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#endif
