// megavox — exact min-cut of a pixel-grid graph on a device (tiled push-relabel; kernels/common/min_cut.h).
//
// The answer is the same bytes on every device: the cut value (the maximum flow, exactly) and the canonical
// minimal source set (the pixels reachable from the source in the residual graph of a maximum flow, which is
// also Boykov-Kolmogorov's final source tree). The kernels solve the reversed graph (reversed_grid_graph), where
// that set is what can still reach the sink once no excess can: the heights of a last global relabel.
#pragma once
#include <cstdint>

#include "megavox/device.h"
#include "megavox/grid_graph.h"

namespace mv {

struct MinCutOptions {
  uint32_t tile = 16;              // tile side in pixels (>= 2); one work-item per tile
  uint32_t discharge_passes = 12;  // passes over the four tile colours between two global relabels
  uint32_t sweeps = 3;             // sweeps over a tile per dispatch (fewer where the device caps loops)
};

struct MinCutStats {
  uint32_t rounds = 0;          // global relabels (each followed by discharge passes but the last)
  uint32_t relabel_passes = 0;  // invalidation and relaxation passes over the four colours, summed over the rounds
};

// Throws mv::Error on an invalid graph (validate_grid_graph) or when the device memory cannot hold it.
MinCut min_cut(Device& dev, const GridGraph& g, const MinCutOptions& options = {}, MinCutStats* stats = nullptr);

}  // namespace mv
