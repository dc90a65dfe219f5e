// Vulkan entry points of the point-cloud LOD kernels, one module per -DMV_ENTRY_<name> (bodies: common/points.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/points.h"

#if defined(MV_ENTRY_point_codes)
layout(push_constant) uniform Args { MvBufU32 xyz; MvBufU64 keys; MvBufU32 index_; MvPointParams p; } args;
void main() { mv_point_codes(args.xyz, args.keys, args.index_, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_rep_count)
layout(push_constant) uniform Args { MvBufU64 codes; MvBufU32 bounds; MvBufU32 cells; MvBufU32 kept; MvPointParams p; } args;
void main() { mv_rep_count(args.codes, args.bounds, args.cells, args.kept, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_rep_select)
layout(push_constant) uniform Args {
  MvBufU64 codes; MvBufU32 bounds; MvBufU32 cells; MvBufU32 offsets; MvBufU32 out_; MvPointParams p;
} args;
void main() {
  mv_rep_select(args.codes, args.bounds, args.cells, args.offsets, args.out_, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#else
#error "define MV_ENTRY_point_codes, MV_ENTRY_rep_count or MV_ENTRY_rep_select"
#endif
