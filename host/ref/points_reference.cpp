#include "points_reference.h"

#include <algorithm>
#include <deque>
#include <memory>
#include <numeric>

namespace mv::ref {

namespace {

// Bit i of x, y, z at bits 3i, 3i+1, 3i+2: written bit by bit, unlike the kernels' magic-number spreads.
uint64_t interleave(uint32_t x, uint32_t y, uint32_t z) {
  uint64_t code = 0;
  for (int i = 0; i < 21; ++i) {
    code |= uint64_t{(x >> i) & 1} << (3 * i);
    code |= uint64_t{(y >> i) & 1} << (3 * i + 1);
    code |= uint64_t{(z >> i) & 1} << (3 * i + 2);
  }
  return code;
}

uint32_t axis_of(uint64_t code, int axis) {
  uint32_t v = 0;
  for (int i = 0; i < 21; ++i) v |= static_cast<uint32_t>((code >> (3 * i + axis)) & 1) << i;
  return v;
}

}  // namespace

std::vector<uint32_t> representatives(std::span<const uint64_t> codes, std::span<const uint32_t> bounds,
                                      uint32_t cell_bits, uint32_t cap) {
  std::vector<uint32_t> out;
  const int64_t side = int64_t{1} << (cell_bits / 3);
  for (size_t g = 0; g + 1 < bounds.size(); ++g) {
    struct Cell {
      uint64_t id;
      uint32_t best;
      int64_t dist;
    };
    std::vector<Cell> cells;
    for (uint32_t i = bounds[g]; i < bounds[g + 1]; ++i) {
      int64_t dist = 0;
      for (int a = 0; a < 3; ++a) {
        const int64_t d = 2 * (axis_of(codes[i], a) % side) + 1 - side;  // twice the offset from the cell centre
        dist += d * d;
      }
      const uint64_t id = codes[i] >> cell_bits;
      if (cells.empty() || cells.back().id != id) cells.push_back({id, i, dist});
      else if (dist < cells.back().dist) cells.back() = {id, i, dist};
    }
    const uint64_t n = cells.size();
    for (uint64_t j = 0; j < n; ++j)
      if (n <= cap || (j + 1) * cap / n > j * cap / n) out.push_back(cells[j].best);
  }
  return out;
}

namespace {

struct RefNode {
  uint32_t level;
  uint64_t prefix;
  uint64_t begin, end;          // its subtree's points in sorted order
  std::vector<uint32_t> chosen;  // sorted positions of its points: all for a leaf, representatives else
  std::unique_ptr<RefNode> child[8];
  bool leaf = true;
};

std::unique_ptr<RefNode> split(const std::vector<uint64_t>& sorted, uint32_t level, uint64_t prefix, uint64_t begin,
                               uint64_t end, const PointLodRule& rule) {
  auto node = std::make_unique<RefNode>();
  node->level = level;
  node->prefix = prefix;
  node->begin = begin;
  node->end = end;
  if (level == rule.depth || end - begin <= rule.max_node_points) {
    for (uint64_t i = begin; i < end; ++i) node->chosen.push_back(static_cast<uint32_t>(i));
    return node;
  }
  node->leaf = false;
  std::vector<uint32_t> candidates;
  uint64_t at = begin;
  for (uint32_t o = 0; o < 8; ++o) {
    uint64_t stop = at;
    while (stop < end && ((sorted[stop] >> (3 * (20 - level))) & 7) == o) ++stop;
    if (stop > at) {
      node->child[o] = split(sorted, level + 1, prefix * 8 + o, at, stop, rule);
      candidates.insert(candidates.end(), node->child[o]->chosen.begin(), node->child[o]->chosen.end());
    }
    at = stop;
  }
  std::vector<uint64_t> codes(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) codes[i] = sorted[candidates[i]];
  const uint32_t fine = level + rule.grid_bits;
  const uint32_t cell_bits = fine >= 21 ? 0 : 3 * (21 - fine);
  const std::vector<uint32_t> bounds{0, static_cast<uint32_t>(codes.size())};
  for (uint32_t pos : representatives(codes, bounds, cell_bits, rule.max_node_points))
    node->chosen.push_back(candidates[pos]);
  return node;
}

}  // namespace

PointHierarchy build_point_hierarchy(const PointColumns& points, const PointCloudInfo& info, const PointLodRule& rule) {
  PointHierarchy h;
  h.source = info;
  h.grid_bits = rule.grid_bits;
  const uint64_t n = points.size();
  h.points_in = h.points_kept = n;
  if (n == 0) return h;
  int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = points.xyz[a];
  for (uint64_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min<int64_t>(lo[a], points.xyz[3 * i + a]);
      hi[a] = std::max<int64_t>(hi[a], points.xyz[3 * i + a]);
    }
  int64_t extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  // The cube: the smallest 2^(21 + shift) units that hold the extent, with shift < 0 for narrow clouds.
  h.shift = -21;
  while (h.shift < 0 ? (extent << -h.shift) >= (int64_t{1} << 21) : (extent >> h.shift) >= (int64_t{1} << 21)) ++h.shift;
  for (int a = 0; a < 3; ++a) h.cube_min[a] = lo[a];

  std::vector<uint64_t> code(n);
  for (uint64_t i = 0; i < n; ++i) {
    uint32_t c[3];
    for (int a = 0; a < 3; ++a) {
      const int64_t d = points.xyz[3 * i + a] - lo[a];
      c[a] = static_cast<uint32_t>(h.shift >= 0 ? d >> h.shift : d << -h.shift);
    }
    code[i] = interleave(c[0], c[1], c[2]);
  }
  std::vector<uint64_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](uint64_t a, uint64_t b) { return code[a] < code[b]; });
  std::vector<uint64_t> sorted(n);
  for (uint64_t i = 0; i < n; ++i) sorted[i] = code[order[i]];

  std::unique_ptr<RefNode> root = split(sorted, 0, 0, 0, n, rule);

  // Breadth-first: a queue visits levels in order and, within a level, parents' children in parent order.
  std::deque<const RefNode*> queue{root.get()};
  while (!queue.empty()) {
    const RefNode* r = queue.front();
    queue.pop_front();
    PointNode node;
    node.code = (uint64_t{1} << (3 * r->level)) | r->prefix;
    node.level = static_cast<uint8_t>(r->level);
    node.subtree_points = r->end - r->begin;
    node.first_point = h.points.size();
    node.point_count = static_cast<uint32_t>(r->chosen.size());
    for (uint32_t pos : r->chosen) h.points.append(points, order[pos], info.extra_bytes);
    if (!r->leaf) {
      node.first_child = static_cast<uint32_t>(h.nodes.size() + 1 + queue.size());
      for (uint32_t o = 0; o < 8; ++o)
        if (r->child[o]) {
          node.child_mask |= static_cast<uint8_t>(1u << o);
          queue.push_back(r->child[o].get());
        }
    }
    if (h.nodes_per_level.size() <= r->level) h.nodes_per_level.resize(r->level + 1);
    ++h.nodes_per_level[r->level];
    h.depth = std::max(h.depth, r->level);
    h.nodes.push_back(node);
  }
  return h;
}

}  // namespace mv::ref
