// Boost.Graph Boykov-Kolmogorov on a pixel grid: one vertex per pixel plus source and sink, each grid edge and
// its reverse as one pair of Boost edges (a residual pair), terminal edges paired with zero-capacity reverses.
// Written apart from the kernels: the neighbour offsets are spelled out here from grid_graph.h's documentation.
#include "min_cut_reference.h"
#include "timing.h"

// Boost 1.74's BK trips GCC 12's -Wmaybe-uninitialized inside its own edge iterators (third-party code), a
// warning given where the template is inlined: off for this whole file.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <chrono>

namespace mv::ref {

namespace {

using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
using Graph = boost::adjacency_list<
    boost::vecS, boost::vecS, boost::directedS,
    boost::property<boost::vertex_index_t, long,
                    boost::property<boost::vertex_color_t, boost::default_color_type,
                                    boost::property<boost::vertex_distance_t, long,
                                                    boost::property<boost::vertex_predecessor_t, Traits::edge_descriptor>>>>,
    boost::property<boost::edge_capacity_t, long,
                    boost::property<boost::edge_residual_capacity_t, long,
                                    boost::property<boost::edge_reverse_t, Traits::edge_descriptor>>>>;

// Neighbour d = (dx, dy): +x, -x, +y, -y, (+1,+1), (-1,-1), (+1,-1), (-1,+1).
constexpr int kDx[8] = {1, -1, 0, 0, 1, -1, 1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, -1, 1};

void add_pair(Graph& graph, size_t u, size_t v, long cap_uv, long cap_vu) {
  auto capacity = boost::get(boost::edge_capacity, graph);
  auto reverse = boost::get(boost::edge_reverse, graph);
  auto e = boost::add_edge(u, v, graph).first;
  auto r = boost::add_edge(v, u, graph).first;
  capacity[e] = cap_uv;
  capacity[r] = cap_vu;
  reverse[e] = r;
  reverse[r] = e;
}

}  // namespace

MinCut bk_min_cut(const GridGraph& g, double* solve_seconds) {
  validate_grid_graph(g);
  const size_t n = size_t{g.width} * g.height, s = n, t = n + 1;
  Graph graph(n + 2);
  for (uint32_t y = 0; y < g.height; ++y)
    for (uint32_t x = 0; x < g.width; ++x) {
      const size_t i = size_t{y} * g.width + x;
      if (g.source[i] != 0) add_pair(graph, s, i, g.source[i], 0);
      if (g.sink[i] != 0) add_pair(graph, i, t, g.sink[i], 0);
      for (uint32_t d = 0; d < g.connectivity; d += 2) {  // each neighbour pair once, from its even side
        const long nx = long{x} + kDx[d], ny = long{y} + kDy[d];
        if (nx < 0 || ny < 0 || nx >= long{g.width} || ny >= long{g.height}) continue;
        const size_t j = size_t(ny) * g.width + size_t(nx);
        const uint32_t ij = g.edges[i * g.connectivity + d], ji = g.edges[j * g.connectivity + (d ^ 1)];
        if (ij != 0 || ji != 0) add_pair(graph, i, j, ij, ji);
      }
    }
  const auto start = std::chrono::steady_clock::now();
  const long flow = boost::boykov_kolmogorov_max_flow(graph, s, t);
  if (solve_seconds) *solve_seconds = seconds_since(start);
  MinCut cut;
  cut.value = static_cast<uint64_t>(flow);
  cut.source_side.resize(n);
  auto color = boost::get(boost::vertex_color, graph);
  for (size_t i = 0; i < n; ++i) cut.source_side[i] = color[i] == boost::black_color ? 1 : 0;
  return cut;
}

std::vector<uint32_t> sink_distances(uint32_t width, uint32_t height, uint32_t connectivity,
                                     const std::vector<uint32_t>& residual, const std::vector<uint32_t>& sink) {
  const size_t n = size_t{width} * height;
  std::vector<uint32_t> dist(n, UINT32_MAX);
  std::vector<size_t> queue;
  queue.reserve(n);
  for (size_t i = 0; i < n; ++i)
    if (sink[i] > 0) {
      dist[i] = 1;
      queue.push_back(i);
    }
  for (size_t head = 0; head < queue.size(); ++head) {
    const size_t v = queue[head];
    const long vx = long(v % width), vy = long(v / width);
    for (uint32_t d = 0; d < connectivity; ++d) {  // u whose edge d leads to v
      const long ux = vx - kDx[d], uy = vy - kDy[d];
      if (ux < 0 || uy < 0 || ux >= long{width} || uy >= long{height}) continue;
      const size_t u = size_t(uy) * width + size_t(ux);
      if (dist[u] != UINT32_MAX || residual[u * connectivity + d] == 0) continue;
      dist[u] = dist[v] + 1;
      queue.push_back(u);
    }
  }
  return dist;
}

}  // namespace mv::ref
