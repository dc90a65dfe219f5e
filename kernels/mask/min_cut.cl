// OpenCL entry points of the min-cut family, both exact: tiled push-relabel (min_cut_seed, min_cut_wave,
// min_cut_active, min_cut_discharge; bodies: common/min_cut.h), one work-item per tile, and Boykov-Kolmogorov over
// regions (min_cut_regions; bodies: common/min_cut_regions.h), one work-item taking region after region.
#include "common/min_cut.h"
#include "common/min_cut_regions.h"

__kernel void min_cut_seed(__global uint* height, __global uint* sink, MvMinCutParams p) {
  mv_min_cut_seed(height, sink, p.width * p.height, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void min_cut_wave(__global uint* height, __global uint* resid, __global uint* flag, __global uint* stamp,
                           __global uint* unfinished, MvMinCutParams p) {
  mv_min_cut_wave(height, resid, flag, stamp, unfinished, p, p.first_tile + MV_GLOBAL_ID());
}

__kernel void min_cut_active(__global uint* excess, __global uint* height, __global uint* flag, MvMinCutParams p) {
  mv_min_cut_active(excess, height, flag, p.width * p.height, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void min_cut_discharge(__global uint* excess, __global uint* height, __global uint* sink,
                               __global uint* resid, __global uint* busy, MvMinCutParams p) {
  mv_min_cut_discharge(excess, height, sink, resid, busy, p, p.first_tile + MV_GLOBAL_ID());
}

__kernel void min_cut_regions(__global uint* resid, __global uint* term, __global uint* node, __global uint* next,
                        __global uint* orphans, __global uint* state, MvMinCutRegionsParams p) {
  mv_bk_items(resid, term, node, next, orphans, state, p);
}
