// Vulkan entry points of the OMiCroN builder's representative kernels, one module per -DMV_ENTRY_<name>
// (bodies: common/omicron.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/omicron.h"

#if defined(MV_ENTRY_omicron_rep_heads)
layout(push_constant) uniform Args { MvBufU32 bounds; MvBufU32 heads; MvRepParams p; } args;
void main() { mv_omicron_rep_heads(args.bounds, args.heads, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_omicron_rep_distance)
layout(push_constant) uniform Args { MvBufU64 codes; MvBufU64 dist; MvRepParams p; } args;
void main() { mv_omicron_rep_distance(args.codes, args.dist, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_omicron_rep_keep)
layout(push_constant) uniform Args { MvBufU32 bounds; MvBufU32 e; MvBufU32 starts; MvBufU32 keep; MvRepParams p; } args;
void main() {
  mv_omicron_rep_keep(args.bounds, args.e, args.starts, args.keep, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_omicron_rep_compact)
layout(push_constant) uniform Args { MvBufU32 keep; MvBufU32 pos; MvBufU32 nearest; MvBufU32 dst; MvRepParams p; } args;
void main() {
  mv_omicron_rep_compact(args.keep, args.pos, args.nearest, args.dst, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_omicron_rep_offsets)
layout(push_constant) uniform Args { MvBufU32 bounds; MvBufU32 e; MvBufU32 pos; MvBufU32 offsets; MvRepParams p; } args;
void main() {
  mv_omicron_rep_offsets(args.bounds, args.e, args.pos, args.offsets, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#else
#error "define MV_ENTRY_omicron_rep_heads, _distance, _keep, _compact or _offsets"
#endif
