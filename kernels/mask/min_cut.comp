// Vulkan entry points of the min-cut family, one module per -DMV_ENTRY_<name>: tiled push-relabel (seed,
// wave, active, discharge; bodies: common/min_cut.h), one invocation per tile, and Boykov-Kolmogorov over
// regions (regions; bodies: common/min_cut_regions.h), one invocation taking region after region.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/min_cut.h"
#include "common/min_cut_regions.h"

#if defined(MV_ENTRY_seed)
MV_ARGS(MvBufU32 height; MvBufU32 sink; MvMinCutParams p;);
void main() {
  mv_min_cut_seed(args.height, args.sink, args.p.width * args.p.height, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_wave)
MV_ARGS(MvBufU32 height; MvBufU32 resid; MvBufU32 flag; MvBufU32 stamp; MvBufU32 unfinished; MvMinCutParams p;);
void main() {
  mv_min_cut_wave(args.height, args.resid, args.flag, args.stamp, args.unfinished, args.p, args.p.first_tile + MV_GLOBAL_ID());
}
#elif defined(MV_ENTRY_active)
MV_ARGS(MvBufU32 excess; MvBufU32 height; MvBufU32 flag; MvMinCutParams p;);
void main() {
  mv_min_cut_active(args.excess, args.height, args.flag, args.p.width * args.p.height, MV_GLOBAL_ID(),
                    MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_discharge)
MV_ARGS(MvBufU32 excess; MvBufU32 height; MvBufU32 sink; MvBufU32 resid; MvBufU32 busy; MvMinCutParams p;);
void main() {
  mv_min_cut_discharge(args.excess, args.height, args.sink, args.resid, args.busy, args.p,
                       args.p.first_tile + MV_GLOBAL_ID());
}
#elif defined(MV_ENTRY_regions)
MV_ARGS(MvBufU32 resid; MvBufU32 term; MvBufU32 node; MvBufU32 next; MvBufU32 orphans; MvBufU32 state;
        MvMinCutRegionsParams p;);
void main() {
  mv_bk_items(args.resid, args.term, args.node, args.next, args.orphans, args.state, args.p);
}
#else
#error "define MV_ENTRY_seed, wave, active, discharge or regions"
#endif
