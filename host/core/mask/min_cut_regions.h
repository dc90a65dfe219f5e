// Exact min-cut by Boykov-Kolmogorov over regions of the grid, merged 2 x 2 a level up to the whole grid
// (kernels/common/min_cut_regions.h).
#pragma once
#include <cstdint>
#include <vector>

#include "megavox/device.h"
#include "megavox/min_cut.h"

namespace mv::mask {

// Cuts the graph whose residual edges are in rb (g's size and connectivity; rb is left holding the residual of a
// maximum flow), with `excess` and `sink` the capacities left on each pixel's source and sink edge, with
// `regions` x `regions` regions in the first level (fewer where the grid is under 2 pixels a region). Returns the
// flow that reached the sink; `reaches` = 1 for the pixels that can still reach it (the sink's search tree).
// st.rounds counts the dispatches.
uint64_t min_cut_regions(Device& dev, const GridGraph& g, uint32_t regions, Buffer& rb,
                         const std::vector<uint32_t>& excess, const std::vector<uint32_t>& sink,
                         std::vector<uint8_t>& reaches, MinCutStats& st);

}  // namespace mv::mask
