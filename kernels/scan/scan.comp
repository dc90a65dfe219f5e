// Vulkan entry points of the exclusive scan, one module per -DMV_ENTRY_<name> (bodies: common/scan.h,
// common/scan_group.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/scan.h"

#if defined(MV_ENTRY_reduce)
layout(push_constant) uniform Args { MvBufU32 in_; MvBufU64 sums; MvScanParams p; } args;
void main() {
  uint b = MV_GLOBAL_ID();
  if (b < args.p.blocks) mv_scan_reduce(args.in_, args.sums, args.p, b);
}
#elif defined(MV_ENTRY_small)
layout(push_constant) uniform Args { MvBufU64 data; MvScanParams p; } args;
void main() {
  if (MV_GLOBAL_ID() == 0u) mv_scan_small(args.data, args.p);
}
#elif defined(MV_ENTRY_apply)
layout(push_constant) uniform Args { MvBufU32 in_; MvBufU32 out_; MvBufU64 sums; MvScanParams p; } args;
void main() {
  uint b = MV_GLOBAL_ID();
  if (b < args.p.blocks) mv_scan_apply(args.in_, args.out_, args.sums, args.p, b);
}
#elif defined(MV_ENTRY_reduce_group)
MV_SHARED(uint64_t, scan_part, MV_SCAN_GROUP);
#include "common/scan_group.h"
layout(push_constant) uniform Args { MvBufU32 in_; MvBufU64 sums; MvScanParams p; } args;
void main() { mv_scan_reduce_group(args.in_, args.sums, args.p, MV_GROUP_ID(), MV_LOCAL_ID(), MV_LOCAL_SIZE()); }
#else
#error "define MV_ENTRY_reduce, _small, _apply or _reduce_group"
#endif
