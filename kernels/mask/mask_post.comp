// Vulkan entry points of mask post-processing, one module per -DMV_ENTRY_<name> (bodies: common/mask_post.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/mask_post.h"

MV_ARGS(MvBufU32 src; MvBufU32 dst; MvMaskPostParams p;);
#if defined(MV_ENTRY_median5)
void main() { mv_mask_median5(args.src, args.dst, args.p, MV_GLOBAL_ID_D(0), MV_GLOBAL_ID_D(1)); }
#elif defined(MV_ENTRY_erode)
void main() { mv_mask_erode(args.src, args.dst, args.p, MV_GLOBAL_ID_D(0), MV_GLOBAL_ID_D(1)); }
#else
#error "define MV_ENTRY_median5 or MV_ENTRY_erode"
#endif
