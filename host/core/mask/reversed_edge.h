// One edge of a grid graph's reversal, read in place: reversed_edges() builds all of them, and a warm-started
// min-cut sums them per pixel without building them.
#pragma once
#include <cstdint>

#include "common/grid_graph.h"
#include "megavox/grid_graph.h"

namespace mv {

// Edge d out of pixel (x, y) in the reversed graph: g's capacity from that neighbour back to (x, y), 0 where d
// leaves the grid.
inline uint32_t reversed_edge(const GridGraph& g, uint32_t x, uint32_t y, uint32_t d) {
  const int64_t nx = int64_t{x} + mv_grid_dx(d), ny = int64_t{y} + mv_grid_dy(d);
  if (nx < 0 || ny < 0 || nx >= g.width || ny >= g.height) return 0;
  return g.edges[(uint64_t(ny) * g.width + uint64_t(nx)) * g.connectivity + (d ^ 1u)];
}

}  // namespace mv
