// Vulkan entry points of unique over sorted keys, one module per -DMV_ENTRY_<name> (bodies: common/unique.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/unique.h"

#if defined(MV_ENTRY_flags)
layout(push_constant) uniform Args { MvBufU64 keys; MvBufU32 flags; MvUniqueParams p; } args;
void main() { mv_unique_flags(args.keys, args.flags, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_compact)
layout(push_constant) uniform Args { MvBufU64 keys; MvBufU32 pos; MvBufU64 out_; MvUniqueParams p; } args;
void main() { mv_unique_compact(args.keys, args.pos, args.out_, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#else
#error "define MV_ENTRY_flags or MV_ENTRY_compact"
#endif
