// Reference min-cut of a pixel-grid graph: Boost.Graph's boykov_kolmogorov_max_flow (header-only, libboost-dev).
// The oracle of the min-cut kernels' tests and the baseline of `megavox bench mask`.
#pragma once
#include "megavox/grid_graph.h"

namespace mv::ref {

// The maximum flow and the final source tree (Boost's black vertices: the pixels reachable from the source in
// the residual graph, which is the canonical minimal source set). Boost's own graph is built first;
// `solve_seconds`, when given, receives the time of the max-flow call alone.
MinCut bk_min_cut(const GridGraph& g, double* solve_seconds = nullptr);

}  // namespace mv::ref
