// Vulkan entry points of the radix sort: one SPIR-V module per (entry, key type), selected at build time
// with -DMV_ENTRY_<name> and -DMV_KEY64 (bodies: common/radix_sort_body.h, common/radix_coop_*.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/radix_sort.h"

#ifdef MV_KEY64
#define MV_KEY uint64_t
#define MvBufKey MvBufU64
#define MV_KCAST(x) MV_U64(x)
#define MV_KFN(f) f##_k64
#define MV_RADIX_KEY_DIGITS 8
#else
#define MV_KEY uint
#define MvBufKey MvBufU32
#define MV_KCAST(x) MV_U32(x)
#define MV_KFN(f) f##_k32
#define MV_RADIX_KEY_DIGITS 4
#endif
#include "common/radix_sort_body.h"

#if defined(MV_ENTRY_or_and)
layout(push_constant) uniform Args { MvBufKey keys; MvBufKey red; MvBufU32 hist; MvRadixParams p; } args;
void main() {
  uint b = MV_GLOBAL_ID();
  if (b < args.p.blocks) MV_KFN(mv_radix_or_and)(args.keys, args.red, args.hist, args.p, b);
}
#elif defined(MV_ENTRY_histogram)
layout(push_constant) uniform Args { MvBufKey keys; MvBufU32 hist; MvRadixParams p; } args;
void main() {
  uint b = MV_GLOBAL_ID();
  if (b < args.p.blocks) MV_KFN(mv_radix_histogram)(args.keys, args.hist, args.p, b);
}
#elif defined(MV_ENTRY_scatter)
layout(push_constant) uniform Args {
  MvBufKey keys_in; MvBufKey keys_out; MvBufU32 vals_in; MvBufU32 vals_out; MvBufU32 offsets; MvRadixParams p;
} args;
void main() {
  uint b = MV_GLOBAL_ID();
  if (b < args.p.blocks)
    MV_KFN(mv_radix_scatter)(args.keys_in, args.keys_out, args.vals_in, args.vals_out, args.offsets, args.p, b);
}
#elif defined(MV_ENTRY_scatter_stream)
layout(push_constant) uniform Args {
  MvBufKey keys_in; MvBufKey keys_out; MvBufU32 vals_in; MvBufU32 vals_out; MvBufU32 offsets; MvRadixParams p;
} args;
void main() {
  uint b = MV_GLOBAL_ID();
  if (b < args.p.blocks)
    MV_KFN(mv_radix_scatter_stream)(args.keys_in, args.keys_out, args.vals_in, args.vals_out, args.offsets, args.p, b);
}
#elif defined(MV_ENTRY_local_sort)
layout(push_constant) uniform Args {
  MvBufKey keys; MvBufKey scratch; MvBufU32 vals; MvBufU32 vscratch; MvBufU32 offsets; MvRadixParams p;
} args;
void main() {
  MV_KFN(mv_radix_local_sort)(args.keys, args.scratch, args.vals, args.vscratch, args.offsets, args.p, MV_GLOBAL_ID());
}
#elif defined(MV_ENTRY_coop_histogram)
MV_SHARED(uint, aux, MV_COOP_AUX);
#include "common/radix_coop_hist.h"
layout(push_constant) uniform Args { MvBufKey keys; MvBufU32 hist; MvRadixParams p; } args;
void main() { MV_KFN(mv_radix_coop_histogram)(args.keys, args.hist, args.p); }
#elif defined(MV_ENTRY_coop_scatter)
MV_SHARED(MV_KEY, ks, MV_COOP_TILE);
MV_SHARED(uint, vs, MV_COOP_TILE);
MV_SHARED(uint, cnt, MV_COOP_COUNTERS);
MV_SHARED(uint, aux, MV_COOP_AUX);
#include "common/radix_coop_scatter.h"
layout(push_constant) uniform Args {
  MvBufKey keys_in; MvBufKey keys_out; MvBufU32 vals_in; MvBufU32 vals_out; MvBufU32 offsets; MvRadixParams p;
} args;
void main() {
  MV_KFN(mv_radix_coop_scatter)(args.keys_in, args.keys_out, args.vals_in, args.vals_out, args.offsets, args.p);
}
#else
#error "define MV_ENTRY_or_and, histogram, scatter, local_sort, coop_histogram or coop_scatter"
#endif
