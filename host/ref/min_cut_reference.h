// Reference min-cut of a pixel-grid graph: Boost.Graph's boykov_kolmogorov_max_flow (header-only, libboost-dev).
// The oracle of the min-cut kernels' tests and the baseline of `megavox bench mask`.
#pragma once
#include <cstdint>
#include <vector>

#include "megavox/grid_graph.h"

namespace mv::ref {

// The maximum flow and the final source tree (Boost's black vertices: the pixels reachable from the source in
// the residual graph, which is the canonical minimal source set). Boost's own graph is built first;
// `solve_seconds`, when given, receives the time of the max-flow call alone.
MinCut bk_min_cut(const GridGraph& g, double* solve_seconds = nullptr);

// Each pixel's distance to the sink by a breadth-first search backwards from it: a pixel with sink capacity is
// one step away, pixel i reaches its neighbour d where residual[i * connectivity + d] > 0; UINT32_MAX where the
// sink cannot be reached. The oracle of the push-relabel solver's global relabel (mv::min_cut_sink_distances).
std::vector<uint32_t> sink_distances(uint32_t width, uint32_t height, uint32_t connectivity,
                                     const std::vector<uint32_t>& residual, const std::vector<uint32_t>& sink);

}  // namespace mv::ref
