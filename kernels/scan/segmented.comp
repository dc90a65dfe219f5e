// Vulkan entry points of the segmented operations, one module per -DMV_ENTRY_<name> (bodies: common/segmented.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/segmented.h"

#if defined(MV_ENTRY_heads)
layout(push_constant) uniform Args { MvBufU64 keys; MvBufU32 heads; MvSegParams p; } args;
void main() { mv_seg_heads(args.keys, args.heads, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_starts)
layout(push_constant) uniform Args { MvBufU32 e; MvBufU32 starts; MvSegParams p; } args;
void main() { mv_seg_starts(args.e, args.starts, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_sum)
layout(push_constant) uniform Args { MvBufU64 prefix; MvBufU32 starts; MvBufU64 sums; MvSegParams p; } args;
void main() { mv_seg_sum(args.prefix, args.starts, args.sums, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_scan)
layout(push_constant) uniform Args { MvBufU64 prefix; MvBufU32 e; MvBufU32 starts; MvBufU64 out_; MvSegParams p; } args;
void main() { mv_seg_scan(args.prefix, args.e, args.starts, args.out_, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_argmin_reduce)
layout(push_constant) uniform Args { MvBufU64 values; MvBufU32 e; MvBufU64 agg; MvSegParams p; } args;
void main() {
  uint b = MV_GLOBAL_ID();
  if (b < args.p.blocks) mv_seg_argmin_reduce(args.values, args.e, args.agg, args.p, b);
}
#elif defined(MV_ENTRY_argmin_small)
layout(push_constant) uniform Args { MvBufU64 agg; MvSegParams p; } args;
void main() {
  if (MV_GLOBAL_ID() == 0u) mv_seg_argmin_small(args.agg, args.p);
}
#elif defined(MV_ENTRY_argmin_apply)
layout(push_constant) uniform Args { MvBufU64 values; MvBufU32 e; MvBufU64 agg; MvBufU32 out_; MvSegParams p; } args;
void main() {
  uint b = MV_GLOBAL_ID();
  if (b < args.p.blocks) mv_seg_argmin_apply(args.values, args.e, args.agg, args.out_, args.p, b);
}
#else
#error "define MV_ENTRY_heads, _starts, _sum, _scan, _argmin_reduce, _argmin_small or _argmin_apply"
#endif
