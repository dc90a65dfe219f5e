// Vulkan entry points of the OMiCroN builder's representative kernels, one module per -DMV_ENTRY_<name>
// (bodies: common/omicron.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/omicron.h"

#if defined(MV_ENTRY_omicron_rep_count)
layout(push_constant) uniform Args {
  MvBufU64 codes; MvBufU32 bounds; MvBufU32 cells; MvBufU32 kept; MvPointParams p;
} args;
void main() {
  mv_omicron_rep_count(args.codes, args.bounds, args.cells, args.kept, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_omicron_rep_select)
layout(push_constant) uniform Args {
  MvBufU64 codes; MvBufU32 bounds; MvBufU32 cells; MvBufU32 offsets; MvBufU32 out_; MvPointParams p;
} args;
void main() {
  mv_omicron_rep_select(args.codes, args.bounds, args.cells, args.offsets, args.out_, args.p, MV_GLOBAL_ID(),
                        MV_GLOBAL_SIZE());
}
#else
#error "define MV_ENTRY_omicron_rep_count or MV_ENTRY_omicron_rep_select"
#endif
