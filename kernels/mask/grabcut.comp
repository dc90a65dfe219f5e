// Vulkan entry points of GrabCut's per-pixel work, one module per -DMV_ENTRY_<name> (bodies: common/grabcut.h,
// sums: common/grabcut_sums.h, which reads the shared array `acc` each summing entry declares first).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/grabcut.h"

#if defined(MV_ENTRY_moments)
MV_SHARED(uint, acc, 200);
#elif defined(MV_ENTRY_kmeans)
MV_SHARED(uint, acc, 80);
#else
MV_SHARED(uint, acc, 2);
#endif
#include "common/grabcut_sums.h"

#define MV_GC_PIXELS(body) for (uint i = MV_GLOBAL_ID(); i < args.p.pixels; i += MV_GLOBAL_SIZE()) body

#if defined(MV_ENTRY_colours)
MV_ARGS(MvBufU32 samples; MvBufU32 colour; MvGrabCutParams p;);
void main() { MV_GC_PIXELS(mv_gc_colours(args.samples, args.colour, args.p, i);) }
#elif defined(MV_ENTRY_edges)
MV_ARGS(MvBufF64 weights; MvBufF64 c; MvBufU32 edges; MvGrabCutParams p;);
void main() { MV_GC_PIXELS(mv_gc_edges(args.weights, args.c, args.edges, args.p, i);) }
#elif defined(MV_ENTRY_terminals)
MV_ARGS(MvBufF64 terms; MvBufF64 c; MvBufU32 q; MvGrabCutParams p;);
void main() { MV_GC_PIXELS(mv_gc_terminals(args.terms, args.c, args.q, args.p, i);) }
#elif defined(MV_ENTRY_seed_d2)
MV_ARGS(MvBufU32 colour; MvBufU32 labels; MvBufU32 d2_bg; MvBufU32 d2_fg; MvGrabCutParams p;);
void main() { MV_GC_PIXELS(mv_gc_seed_d2(args.colour, args.labels, args.d2_bg, args.d2_fg, args.p, i);) }
#elif defined(MV_ENTRY_seed_find)
MV_ARGS(MvBufU64 scan_bg; MvBufU64 scan_fg; MvBufU32 found; MvGrabCutParams p;);
void main() { MV_GC_PIXELS(mv_gc_seed_find(args.scan_bg, args.scan_fg, args.found, args.p, i);) }
#elif defined(MV_ENTRY_beta_sum)
MV_ARGS(MvBufU32 colour; MvBufU32 sums; MvGrabCutParams p;);
void main() { mv_gc_beta_sum(args.colour, args.sums, args.p); }
#elif defined(MV_ENTRY_smooth_sum)
MV_ARGS(MvBufU32 colour; MvBufF64 c; MvBufF64 weights; MvBufU32 sums; MvGrabCutParams p;);
void main() { mv_gc_smooth_sum(args.colour, args.c, args.weights, args.sums, args.p); }
#elif defined(MV_ENTRY_data)
MV_ARGS(MvBufU32 colour; MvBufU32 labels; MvBufU32 comp; MvBufF64 c; MvBufF64 terms; MvBufU32 sums;
        MvGrabCutParams p;);
void main() { mv_gc_data(args.colour, args.labels, args.comp, args.c, args.terms, args.sums, args.p); }
#elif defined(MV_ENTRY_moments)
MV_ARGS(MvBufU32 colour; MvBufU32 labels; MvBufU32 comp; MvBufU32 sums; MvGrabCutParams p;);
void main() { mv_gc_moments(args.colour, args.labels, args.comp, args.sums, args.p); }
#elif defined(MV_ENTRY_kmeans)
MV_ARGS(MvBufU32 colour; MvBufU32 labels; MvBufU32 comp; MvBufF64 c; MvBufU32 sums; MvGrabCutParams p;);
void main() { mv_gc_kmeans(args.colour, args.labels, args.comp, args.c, args.sums, args.p); }
#elif defined(MV_ENTRY_labels)
MV_ARGS(MvBufU32 source_side; MvBufU32 labels; MvBufU32 sums; MvGrabCutParams p;);
void main() { mv_gc_labels(args.source_side, args.labels, args.sums, args.p); }
#else
#error "define MV_ENTRY_<name> of a GrabCut kernel"
#endif
