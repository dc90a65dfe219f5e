// Vulkan entry points of the voxel colour kernels, one module per -DMV_ENTRY_<name> (bodies: common/colour.h,
// common/quantize.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/colour.h"
#include "common/quantize.h"

#if defined(MV_ENTRY_pack_keys)
layout(push_constant) uniform Args { MvBufU64 keys; MvBufU32 rgb; MvColourParams p; } args;
void main() { mv_colour_pack_keys(args.keys, args.rgb, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_unpack)
layout(push_constant) uniform Args { MvBufU32 rgb; MvBufU32 planes; MvColourParams p; } args;
void main() { mv_colour_unpack(args.rgb, args.planes, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_level)
layout(push_constant) uniform Args { MvBufU64 keys; MvBufU64 sums; MvBufU32 planes; MvColourParams p; } args;
void main() { mv_colour_level(args.keys, args.sums, args.planes, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_parent_keys)
layout(push_constant) uniform Args { MvBufU64 keys; MvBufU32 starts; MvBufU64 up; MvColourParams p; } args;
void main() { mv_colour_parent_keys(args.keys, args.starts, args.up, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_starts)
layout(push_constant) uniform Args { MvBufU64 keys; MvBufU32 rgb; MvBufU32 planes; MvColourParams p; } args;
void main() { mv_colour_starts(args.keys, args.rgb, args.planes, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_nodes)
#if defined(MV_COLOUR_WIDE)
#define MV_COLOUR_SUMS_WIDE 1u
#else
#define MV_COLOUR_SUMS_WIDE 0u
#endif
layout(push_constant) uniform Args {
  MvBufU64 keys; MvBufU32 planes; MvBufU32 sums; MvBufU32 attributes; MvColourParams p;
} args;
void main() {
  mv_colour_nodes(args.keys, args.planes, args.sums, args.attributes, args.p, MV_COLOUR_SUMS_WIDE, MV_GLOBAL_ID(),
                  MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_quantize_nearest)
layout(push_constant) uniform Args {
  MvBufF64 lab; MvBufF64 centres; MvBufU32 order; MvBufU32 cluster; MvBufU32 moved; MvQuantizeParams p;
} args;
void main() {
  mv_quantize_nearest(args.lab, args.centres, args.order, args.cluster, args.moved, args.p, MV_GLOBAL_ID(),
                      MV_GLOBAL_SIZE());
}
#else
#error "define MV_ENTRY_pack_keys, _unpack, _level, _parent_keys, _starts, _nodes or _quantize_nearest"
#endif
