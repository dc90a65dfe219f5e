// megavox — pixel-grid graphs for min-cut (masks): plain data, no device types.
//
// A W x H grid, 4- or 8-connected, with integer capacities: source -> pixel, pixel -> sink and pixel ->
// neighbour d (numbering in kernels/common/grid_graph.h: d = 0 +x, 1 -x, 2 +y, 3 -y, 4 (+1,+1), 5 (-1,-1),
// 6 (+1,-1), 7 (-1,+1); the reverse of d is d ^ 1). Edges that would leave the grid have capacity 0.
#pragma once
#include <cstdint>
#include <vector>

namespace mv {

struct GridGraph {
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t connectivity = 8;     // 4 or 8
  std::vector<uint32_t> source;  // width * height: capacity source -> pixel
  std::vector<uint32_t> sink;    // width * height: capacity pixel -> sink
  std::vector<uint32_t> edges;   // width * height * connectivity: [pixel * connectivity + d], pixel -> neighbour d
};

// The largest total capacity (every source, sink and edge capacity summed) a graph may have: every flow and
// residual value then fits in 31 bits, on the host and in the kernels.
inline constexpr uint64_t kMaxGraphCapacity = (uint64_t{1} << 31) - 1;

// Returns the total capacity. Throws mv::Error saying what is wrong: a zero-sized grid, connectivity other than
// 4 or 8, array sizes that do not match the grid, capacity on an edge leaving the grid, or a total capacity
// over kMaxGraphCapacity.
uint64_t validate_grid_graph(const GridGraph& g);

// The same graph with every edge reversed and source and sink swapped (a cut (S, T) of g is the cut (T, S) of
// the result, at the same value).
GridGraph reversed_grid_graph(const GridGraph& g);
// Its edges alone (edges[i * connectivity + d] = g's capacity from neighbour d to i).
std::vector<uint32_t> reversed_edges(const GridGraph& g);

// A minimum cut: its value (= the maximum flow) and the canonical minimal source set, the pixels reachable
// from the source in the residual graph of a maximum flow (1 = source side).
struct MinCut {
  uint64_t value = 0;
  std::vector<uint8_t> source_side;
};

}  // namespace mv
