// Validation and reversal of pixel-grid graphs (include/megavox/grid_graph.h).
#include "megavox/grid_graph.h"

#include <string>

#include "../kernels/common/grid_graph.h"
#include "megavox/error.h"

namespace mv {

namespace {

bool inside(const GridGraph& g, uint32_t x, uint32_t y, uint32_t d) {
  const int64_t nx = int64_t{x} + mv_grid_dx(d), ny = int64_t{y} + mv_grid_dy(d);
  return nx >= 0 && ny >= 0 && nx < g.width && ny < g.height;
}

}  // namespace

void validate_grid_graph(const GridGraph& g) {
  if (g.width == 0 || g.height == 0) throw Error("grid graph: the grid is empty");
  if (uint64_t{g.width} * g.height > (uint64_t{1} << 30))
    throw Error("grid graph: " + std::to_string(g.width) + " x " + std::to_string(g.height) +
                " pixels is over the 2^30 a min-cut takes");
  if (g.connectivity != 4 && g.connectivity != 8)
    throw Error("grid graph: connectivity " + std::to_string(g.connectivity) + " (4 or 8 expected)");
  const uint64_t n = uint64_t{g.width} * g.height;
  if (g.source.size() != n || g.sink.size() != n || g.edges.size() != n * g.connectivity)
    throw Error("grid graph: capacity arrays do not match the " + std::to_string(g.width) + " x " +
                std::to_string(g.height) + " grid");
  uint64_t total = 0;
  for (uint32_t y = 0; y < g.height; ++y)
    for (uint32_t x = 0; x < g.width; ++x) {
      const uint64_t i = uint64_t{y} * g.width + x;
      total += uint64_t{g.source[i]} + g.sink[i];
      for (uint32_t d = 0; d < g.connectivity; ++d) {
        const uint32_t c = g.edges[i * g.connectivity + d];
        if (c != 0 && !inside(g, x, y, d))
          throw Error("grid graph: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") has capacity " +
                      std::to_string(c) + " on edge " + std::to_string(d) + ", which leaves the grid");
        total += c;
      }
      if (total > kMaxGraphCapacity)
        throw Error("grid graph: the total capacity passes 2^31 - 1 (quantize the weights more coarsely)");
    }
}

std::vector<uint32_t> reversed_edges(const GridGraph& g) {
  std::vector<uint32_t> edges(g.edges.size(), 0);
  const uint32_t conn = g.connectivity;
  for (uint32_t d = 0; d < conn; ++d) {
    const int dx = mv_grid_dx(d), dy = mv_grid_dy(d);
    const int64_t step = int64_t{dy} * g.width + dx;
    // Rows and columns whose neighbour d is inside the grid.
    const uint32_t y0 = dy < 0 ? 1 : 0, y1 = dy > 0 ? g.height - 1 : g.height;
    const uint32_t x0 = dx < 0 ? 1 : 0, x1 = dx > 0 ? g.width - 1 : g.width;
    for (uint32_t y = y0; y < y1; ++y)
      for (uint32_t x = x0; x < x1; ++x) {
        const uint64_t i = uint64_t{y} * g.width + x, j = uint64_t(int64_t(i) + step);
        edges[i * conn + d] = g.edges[j * conn + (d ^ 1u)];  // j -> i becomes i -> j
      }
  }
  return edges;
}

GridGraph reversed_grid_graph(const GridGraph& g) {
  GridGraph r;
  r.width = g.width;
  r.height = g.height;
  r.connectivity = g.connectivity;
  r.source = g.sink;
  r.sink = g.source;
  r.edges = reversed_edges(g);
  return r;
}

}  // namespace mv
