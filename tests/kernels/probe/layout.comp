// Vulkan entry points of the layout probes, one module per -DMV_ENTRY_<name> (bodies: bodies/layout_probe.h):
// the struct arrives in push constants after one buffer address, as parameters do in every kernel.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "../bodies/layout_probe.h"

#if defined(MV_ENTRY_probe_morton_params)
#define MV_PROBE_T MvMortonParams
#define MV_PROBE_FN mv_probe_morton_params
#elif defined(MV_ENTRY_probe_radix_params)
#define MV_PROBE_T MvRadixParams
#define MV_PROBE_FN mv_probe_radix_params
#elif defined(MV_ENTRY_probe_scan_params)
#define MV_PROBE_T MvScanParams
#define MV_PROBE_FN mv_probe_scan_params
#elif defined(MV_ENTRY_probe_unique_params)
#define MV_PROBE_T MvUniqueParams
#define MV_PROBE_FN mv_probe_unique_params
#elif defined(MV_ENTRY_probe_cache_params)
#define MV_PROBE_T MvCacheParams
#define MV_PROBE_FN mv_probe_cache_params
#elif defined(MV_ENTRY_probe_lang_params)
#define MV_PROBE_T MvLangParams
#define MV_PROBE_FN mv_probe_lang_params
#elif defined(MV_ENTRY_probe_voxelize_params)
#define MV_PROBE_T MvVoxelizeParams
#define MV_PROBE_FN mv_probe_voxelize_params
#elif defined(MV_ENTRY_probe_dag_params)
#define MV_PROBE_T MvDagParams
#define MV_PROBE_FN mv_probe_dag_params
#elif defined(MV_ENTRY_probe_trace_params)
#define MV_PROBE_T MvTraceParams
#define MV_PROBE_FN mv_probe_trace_params
#elif defined(MV_ENTRY_probe_secondary_params)
#define MV_PROBE_T MvSecondaryParams
#define MV_PROBE_FN mv_probe_secondary_params
#elif defined(MV_ENTRY_probe_beam_params)
#define MV_PROBE_T MvBeamParams
#define MV_PROBE_FN mv_probe_beam_params
#elif defined(MV_ENTRY_probe_ray)
#define MV_PROBE_T MvRay
#define MV_PROBE_FN mv_probe_ray
#elif defined(MV_ENTRY_probe_hit)
#define MV_PROBE_T MvHit
#define MV_PROBE_FN mv_probe_hit
#elif defined(MV_ENTRY_probe_point_params)
#define MV_PROBE_T MvPointParams
#define MV_PROBE_FN mv_probe_point_params
#elif defined(MV_ENTRY_probe_splat_params)
#define MV_PROBE_T MvSplatParams
#define MV_PROBE_FN mv_probe_splat_params
#elif defined(MV_ENTRY_probe_min_cut_params)
#define MV_PROBE_T MvMinCutParams
#define MV_PROBE_FN mv_probe_min_cut_params
#elif defined(MV_ENTRY_probe_min_cut_regions_params)
#define MV_PROBE_T MvMinCutRegionsParams
#define MV_PROBE_FN mv_probe_min_cut_regions_params
#elif defined(MV_ENTRY_probe_mask_post_params)
#define MV_PROBE_T MvMaskPostParams
#define MV_PROBE_FN mv_probe_mask_post_params
#elif defined(MV_ENTRY_probe_seg_params)
#define MV_PROBE_T MvSegParams
#define MV_PROBE_FN mv_probe_seg_params
#elif defined(MV_ENTRY_probe_rep_params)
#define MV_PROBE_T MvRepParams
#define MV_PROBE_FN mv_probe_rep_params
#elif defined(MV_ENTRY_probe_grabcut_params)
#define MV_PROBE_T MvGrabCutParams
#define MV_PROBE_FN mv_probe_grabcut_params
#elif defined(MV_ENTRY_probe_gather_params)
#define MV_PROBE_T MvGatherParams
#define MV_PROBE_FN mv_probe_gather_params
#elif defined(MV_ENTRY_probe_colour_params)
#define MV_PROBE_T MvColourParams
#define MV_PROBE_FN mv_probe_colour_params
#elif defined(MV_ENTRY_probe_quantize_params)
#define MV_PROBE_T MvQuantizeParams
#define MV_PROBE_FN mv_probe_quantize_params
#else
#error "define MV_ENTRY_probe_<struct>"
#endif

layout(push_constant) uniform Args { MvBufU32 dst; MV_PROBE_T p; } a;
void main() {
  if (MV_GLOBAL_ID() == 0u) MV_PROBE_FN(a.dst, a.p);
}
