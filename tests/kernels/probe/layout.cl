// OpenCL entry points of the layout probes, one per shared struct (bodies: bodies/layout_probe.h).
#include "../bodies/layout_probe.h"

#define MV_PROBE_ENTRY(name, T) \
  __kernel void probe_##name(__global uint* dst, T p) { if (MV_GLOBAL_ID() == 0u) mv_probe_##name(dst, p); }
MV_PROBE_ENTRY(morton_params, MvMortonParams)
MV_PROBE_ENTRY(radix_params, MvRadixParams)
MV_PROBE_ENTRY(scan_params, MvScanParams)
MV_PROBE_ENTRY(unique_params, MvUniqueParams)
MV_PROBE_ENTRY(cache_params, MvCacheParams)
MV_PROBE_ENTRY(lang_params, MvLangParams)
MV_PROBE_ENTRY(voxelize_params, MvVoxelizeParams)
MV_PROBE_ENTRY(dag_params, MvDagParams)
MV_PROBE_ENTRY(trace_params, MvTraceParams)
MV_PROBE_ENTRY(secondary_params, MvSecondaryParams)
MV_PROBE_ENTRY(beam_params, MvBeamParams)
MV_PROBE_ENTRY(ray, MvRay)
MV_PROBE_ENTRY(hit, MvHit)
MV_PROBE_ENTRY(point_params, MvPointParams)
MV_PROBE_ENTRY(splat_params, MvSplatParams)
MV_PROBE_ENTRY(min_cut_params, MvMinCutParams)
MV_PROBE_ENTRY(min_cut_regions_params, MvMinCutRegionsParams)
MV_PROBE_ENTRY(mask_post_params, MvMaskPostParams)
MV_PROBE_ENTRY(seg_params, MvSegParams)
MV_PROBE_ENTRY(rep_params, MvRepParams)
MV_PROBE_ENTRY(grabcut_params, MvGrabCutParams)
MV_PROBE_ENTRY(gather_params, MvGatherParams)
MV_PROBE_ENTRY(colour_params, MvColourParams)
MV_PROBE_ENTRY(quantize_params, MvQuantizeParams)
