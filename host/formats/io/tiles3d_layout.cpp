#include "tiles3d_layout.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>

#include "megavox/error.h"

namespace mv::io {

namespace {

[[noreturn]] void inconsistent(const std::string& what) {
  throw Error("the point hierarchy is inconsistent (a bug in its builder): " + what);
}

std::string node_label(const PointHierarchy& h, size_t i) {
  char code[32];
  std::snprintf(code, sizeof code, "%#llx", static_cast<unsigned long long>(h.nodes[i].code));
  return "node " + std::to_string(i) + " (code " + code + ")";
}

// Breadth-first, root first, children contiguous and in octant order, codes and levels matching: then every
// node is reached exactly once from the root.
void check_tree(const PointHierarchy& h, const std::vector<bool>& elsewhere) {
  const auto& nodes = h.nodes;
  if (nodes.empty()) inconsistent("it has no nodes");
  if (nodes[0].code != 1 || nodes[0].level != 0) inconsistent("node 0 is not the root (code 1, level 0)");
  if (h.shift > 40 || h.shift < -21) inconsistent("shift " + std::to_string(h.shift) + " is beyond a 64-bit grid");
  const uint64_t columns = h.points.size();
  if (h.points.xyz.size() != 3 * columns) inconsistent("the xyz column is not 3 values per point");
  if ((h.source.attributes & kPointRgb) && h.points.rgb.size() != 3 * columns)
    inconsistent("it has RGB, but the rgb column is not 3 values per point");
  size_t next_child = 1;
  uint64_t leaf_points = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const PointNode& n = nodes[i];
    if (n.level > 21 || n.code >> (3 * n.level) != 1)
      inconsistent(node_label(h, i) + " does not match its level " + std::to_string(n.level));
    const bool held = elsewhere.empty() || !elsewhere.at(i);
    if (held && (n.first_point > columns || n.point_count > columns - n.first_point))
      inconsistent(node_label(h, i) + "'s points lie beyond the " + std::to_string(columns) + " points held");
    if (n.leaf()) {
      leaf_points += n.point_count;
      continue;
    }
    if (n.first_child != next_child)
      inconsistent(node_label(h, i) + "'s children start at " + std::to_string(n.first_child) + ", not at " +
                   std::to_string(next_child) + " as breadth-first order puts them");
    next_child += static_cast<size_t>(std::popcount(n.child_mask));
    if (next_child > nodes.size()) inconsistent(node_label(h, i) + "'s children lie beyond the last node");
    size_t c = n.first_child;
    for (uint32_t o = 0; o < 8; ++o) {
      if (!(n.child_mask >> o & 1)) continue;
      if (nodes[c].code != (n.code << 3 | o) || nodes[c].level != n.level + 1)
        inconsistent(node_label(h, c) + " is not child " + std::to_string(o) + " of " + node_label(h, i));
      ++c;
    }
  }
  if (next_child != nodes.size())
    inconsistent(std::to_string(nodes.size() - next_child) + " nodes are no node's children");
  if (leaf_points != h.points_kept)
    inconsistent("its leaves hold " + std::to_string(leaf_points) + " points, but it says it kept " +
                 std::to_string(h.points_kept));
}

std::string path_name(uint64_t code, uint32_t level) {
  std::string name = "r";
  for (uint32_t l = level; l-- > 0;) name += static_cast<char>('0' + (code >> (3 * l) & 7));
  return name;
}

// The cube of a node: its Morton bits (x lowest, as kernels/common/morton.h) give its cell at its level.
void place(const PointHierarchy& h, const PointNode& n, const TileFrame& f, TileLayout& t) {
  const double side = std::ldexp(1.0, static_cast<int>(21 + h.shift - n.level));  // grid units
  for (int a = 0; a < 3; ++a) {
    uint64_t cell = 0;
    for (uint32_t l = 0; l < n.level; ++l) cell |= (n.code >> (3 * l + a) & 1) << l;
    const double lo = static_cast<double>(h.cube_min[a]) + static_cast<double>(cell) * side;
    t.center[a] = (h.source.offset[a] + h.source.scale[a] * (lo + side / 2) - f.origin[a]) * f.factor[a];
    t.half[a] = std::abs(h.source.scale[a] * f.factor[a]) * side / 2;
  }
}

}  // namespace

TileLayout tile_box(const PointHierarchy& h, const PointNode& n, const TileFrame& frame) {
  TileLayout t;
  t.name = path_name(n.code, n.level);
  place(h, n, frame, t);
  return t;
}

std::vector<TileLayout> tiles3d_layout(const PointHierarchy& h, const TileFrame& frame,
                                       const std::vector<bool>& elsewhere) {
  check_tree(h, elsewhere);
  std::vector<TileLayout> tiles(h.nodes.size());
  for (size_t i = 0; i < h.nodes.size(); ++i) tiles[i] = tile_box(h, h.nodes[i], frame);
  // Children come after their parent: going backwards, a node's children are done before it.
  for (size_t i = h.nodes.size(); i-- > 0;) {
    const PointNode& n = h.nodes[i];
    if (n.leaf()) continue;
    const TileLayout& t = tiles[i];
    const double side = 2 * std::max({t.half[0], t.half[1], t.half[2]});
    double e = n.point_count ? side / std::sqrt(static_cast<double>(n.point_count)) : side;
    double children = 0;
    for (int c = 0; c < std::popcount(n.child_mask); ++c)
      children = std::max(children, tiles[n.first_child + c].geometric_error);
    tiles[i].geometric_error = e > children ? e : 2 * children;
  }
  return tiles;
}

double tileset_geometric_error(const std::vector<TileLayout>& tiles) {
  const TileLayout& root = tiles.at(0);
  const double side = 2 * std::max({root.half[0], root.half[1], root.half[2]});
  return std::max(side, 2 * root.geometric_error);
}

}  // namespace mv::io
