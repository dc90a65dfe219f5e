// Vulkan entry points of ray traversal, one module per -DMV_ENTRY_<name> (bodies: common/trace.h,
// common/secondary.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/secondary.h"
#include "common/trace_beam.h"
#include "common/trace_colour_paged.h"

#if defined(MV_ENTRY_trace_rays)
/* MV_TRACE_ENC: the encoding family, MV_TRACE_PARAMS: level starts from the parameters; constants (see trace.cl) */
layout(push_constant) uniform Args {
  MvBufF32 rays; MvBufF32 cam; MvBufU32 words; MvBufU32 bricks; MvBufU32 lvl_off; MvBufU32 out_; MvTraceParams p;
} a;
void main() {
  mv_trace_rays(a.rays, a.cam, a.words, a.bricks, a.lvl_off, a.words, a.words, a.out_, a.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_TRACE_ENC,
                MV_TRACE_PARAMS != 0u ? MV_TRACE_STARTS_IN_PARAMS : 0u);
}
#elif defined(MV_ENTRY_trace_rays_paged)
/* the page cache's buffers (see trace.cl); one source for rays or camera keeps the push constants at 128 bytes;
 * MV_TRACE_ENC: MV_ENC_PAGED or MV_ENC_PAGED_SSVDAG; MV_TRACE_LRU: stamp usage (1) or not (0, see trace.cl);
 * MV_TRACE_PARAMS: a paged ssvdag's level starts from the parameters (1) or the table (0); MV_TRACE_REL (1, where
 * defined): a word stream's pointers count from their level's start */
#if !defined(MV_TRACE_REL)
#define MV_TRACE_REL 0u
#endif
layout(push_constant) uniform Args {
  MvBufF32 src; MvBufU32 slots; MvBufU32 table; MvBufU32 usage; MvBufU32 request; MvBufU32 out_; MvTraceParams p;
} a;
void main() {
  mv_trace_rays(a.src, a.src, a.slots, a.table, a.table, a.usage, a.request, a.out_, a.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_TRACE_ENC,
                (MV_TRACE_LRU != 0u ? MV_TRACE_STAMPS : 0u) | (MV_TRACE_PARAMS != 0u ? MV_TRACE_STARTS_IN_PARAMS : 0u) |
                (MV_TRACE_REL != 0u ? MV_TRACE_RELATIVE : 0u));
}
#elif defined(MV_ENTRY_secondary_flags)
layout(push_constant) uniform Args {
  MvBufU32 hits; MvBufU32 flags; MvSecondaryParams p;
} a;
void main() { mv_secondary_flags(a.hits, a.flags, a.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_secondary_rays)
layout(push_constant) uniform Args {
  MvBufF32 rays; MvBufF32 cam; MvBufU32 hits; MvBufU32 listed; MvBufF32 table; MvBufU32 out_; MvSecondaryParams p;
} a;
void main() { mv_secondary_rays(a.rays, a.cam, a.hits, a.listed, a.table, a.out_, a.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_beam_pack)
layout(push_constant) uniform Args { MvBufU32 counts; MvBufU32 full; MvBeamParams p; } a;
void main() { mv_beam_pack(a.counts, a.full, a.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_beam_dilate)
layout(push_constant) uniform Args { MvBufU32 full; MvBufU32 marked; MvBeamParams p; } a;
void main() { mv_beam_dilate(a.full, a.marked, a.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_beam_starts)
layout(push_constant) uniform Args { MvBufU32 marked; MvBufU32 cam; MvBeamParams p; } a;
void main() { mv_beam_starts(a.marked, a.cam, a.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_hit_colours)
/* MV_TRACE_ENC: the encoding family, a constant (see trace.cl) */
layout(push_constant) uniform Args {
  MvBufU32 hits; MvBufU32 words; MvBufU32 bricks; MvBufU32 meta; MvBufU32 colours; MvBufU32 out_; MvTraceParams p;
} a;
void main() {
  mv_hit_colours(a.hits, a.words, a.bricks, a.meta, a.colours, a.out_, a.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_TRACE_ENC);
}
#elif defined(MV_ENTRY_hit_entries_paged)
/* MV_TRACE_ENC: MV_ENC_PAGED or MV_ENC_PAGED_SSVDAG (see trace.cl) */
layout(push_constant) uniform Args {
  MvBufU32 hits; MvBufU32 slots; MvBufU32 table; MvBufU32 plane; MvBufU32 out_; MvTraceParams p;
} a;
void main() {
  mv_paged_hit_entries(a.hits, a.slots, a.table, a.plane, a.out_, a.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE(), MV_TRACE_ENC);
}
#endif
