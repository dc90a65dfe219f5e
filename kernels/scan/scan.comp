// Vulkan entry points of the exclusive scan, one module per -DMV_ENTRY_<name> (bodies: common/scan.h).
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
#else
#error "define MV_ENTRY_reduce, MV_ENTRY_small or MV_ENTRY_apply"
#endif
