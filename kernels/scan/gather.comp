// Vulkan entry point of the record gather (body: common/gather.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/gather.h"

layout(push_constant) uniform Args { MvBufU32 src; MvBufU32 index; MvBufU32 dst; MvGatherParams p; } args;
void main() { mv_gather_records(args.src, args.index, args.dst, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
