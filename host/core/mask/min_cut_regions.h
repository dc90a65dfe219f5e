// Exact min-cut by Boykov-Kolmogorov over regions of the grid, merged 2 x 2 a level while the levels keep
// enough regions (kernels/common/min_cut_regions.h).
#pragma once
#include <cstdint>
#include <vector>

#include "megavox/device.h"
#include "megavox/min_cut.h"

namespace mv::mask {

// Cuts the graph whose residual edges are in rb (g's size and connectivity), with `excess` and `sink` the
// capacities left on each pixel's source and sink edge, with `regions` x `regions` regions in the first level
// (fewer where the grid is under 2 pixels a region), merged while the next level has `least` regions or more.
// Returns the flow that reached the sink. When the last level ran was the whole grid, `finished` is true, rb holds
// the residual of a maximum flow and `reaches` = 1 for the pixels that can still reach the sink (the sink's search
// tree); else rb holds the regions' flow and `excess` and `sink` what is left on the terminals, for push-relabel
// to finish. st.rounds counts the dispatches.
uint64_t min_cut_regions(Device& dev, const GridGraph& g, uint32_t regions, uint32_t least, Buffer& rb,
                         std::vector<uint32_t>& excess, std::vector<uint32_t>& sink, std::vector<uint8_t>& reaches,
                         MinCutStats& st, bool& finished);

}  // namespace mv::mask
