// Validation and reversal of pixel-grid graphs (include/megavox/grid_graph.h).
#include "megavox/grid_graph.h"

#include <algorithm>
#include <numeric>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "common/grid_graph.h"
#include "megavox/error.h"
#include "reversed_edge.h"

namespace mv {

namespace {

bool inside(const GridGraph& g, uint32_t x, uint32_t y, uint32_t d) {
  const int64_t nx = int64_t{x} + mv_grid_dx(d), ny = int64_t{y} + mv_grid_dy(d);
  return nx >= 0 && ny >= 0 && nx < g.width && ny < g.height;
}

// Pixel (x, y)'s first edge with capacity that leaves the grid, or conn when none.
uint32_t leaving_edge(const GridGraph& g, uint32_t x, uint32_t y) {
  const uint64_t i = uint64_t{y} * g.width + x;
  for (uint32_t d = 0; d < g.connectivity; ++d)
    if (g.edges[i * g.connectivity + d] != 0 && !inside(g, x, y, d)) return d;
  return g.connectivity;
}

// The sum of v, or the first partial sum over `cap` (blocks of 2^16 values cannot wrap 64 bits).
uint64_t sum_until(const std::vector<uint32_t>& v, uint64_t total, uint64_t cap) {
  constexpr size_t kBlock = size_t{1} << 16;
  for (size_t at = 0; at < v.size() && total <= cap; at += kBlock) {
    const size_t end = std::min(v.size(), at + kBlock);
    total = std::accumulate(v.begin() + at, v.begin() + end, total,
                            [](uint64_t a, uint32_t b) { return a + b; });
  }
  return total;
}

}  // namespace

uint64_t validate_grid_graph(const GridGraph& g) {
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
  // Only the border's pixels have edges that leave the grid: visited in pixel order, the first one named.
  for (uint32_t y = 0; y < g.height; ++y) {
    const uint32_t step = y == 0 || y + 1 == g.height ? 1 : std::max<uint32_t>(g.width - 1, 1);
    for (uint32_t x = 0; x < g.width; x += step) {
      const uint32_t d = leaving_edge(g, x, y);
      if (d == g.connectivity) continue;
      throw Error("grid graph: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") has capacity " +
                  std::to_string(g.edges[(uint64_t{y} * g.width + x) * g.connectivity + d]) + " on edge " +
                  std::to_string(d) + ", which leaves the grid");
    }
  }
  uint64_t total = sum_until(g.source, 0, kMaxGraphCapacity);
  total = sum_until(g.sink, total, kMaxGraphCapacity);
  total = sum_until(g.edges, total, kMaxGraphCapacity);
  if (total > kMaxGraphCapacity)
    throw Error("grid graph: the total capacity passes 2^31 - 1 (quantize the weights more coarsely)");
  return total;
}

std::vector<uint32_t> reversed_edges(const GridGraph& g) {
  std::vector<uint32_t> edges(g.edges.size());
  const uint32_t conn = g.connectivity;
  // One pixel at a time, all its edges: its neighbours' words share cache lines with the next pixel's.
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, g.height, 16), [&](const tbb::blocked_range<uint32_t>& rows) {
    for (uint32_t y = rows.begin(); y < rows.end(); ++y)
      for (uint32_t x = 0; x < g.width; ++x)
        for (uint32_t d = 0; d < conn; ++d) edges[(uint64_t{y} * g.width + x) * conn + d] = reversed_edge(g, x, y, d);
  });
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
