#include "points_oracles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <set>
#include <tuple>

namespace mv::test {

namespace {

// Point p with every attribute, as one comparable record.
std::array<int64_t, 10> record(const PointColumns& c, uint64_t p) {
  std::array<int64_t, 10> r{};
  for (int a = 0; a < 3; ++a) r[a] = c.xyz[3 * p + a];
  if (!c.rgb.empty())
    for (int a = 0; a < 3; ++a) r[3 + a] = c.rgb[3 * p + a];
  if (!c.intensity.empty()) r[6] = c.intensity[p];
  if (!c.normal.empty())
    for (int a = 0; a < 3; ++a) {
      uint32_t bits;
      std::memcpy(&bits, &c.normal[3 * p + a], 4);
      r[7 + a] = bits;
    }
  return r;
}

}  // namespace

void expect_same(const PointHierarchy& a, const PointHierarchy& b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    const PointNode &x = a.nodes[i], &y = b.nodes[i];
    ASSERT_EQ(std::tie(x.code, x.first_point, x.subtree_points, x.point_count, x.first_child, x.child_mask, x.level),
              std::tie(y.code, y.first_point, y.subtree_points, y.point_count, y.first_child, y.child_mask, y.level))
        << "node " << i;
  }
  EXPECT_EQ(a.points.xyz, b.points.xyz);
  EXPECT_EQ(a.points.rgb, b.points.rgb);
  EXPECT_EQ(a.points.normal, b.points.normal);
  EXPECT_EQ(a.points.intensity, b.points.intensity);
  EXPECT_EQ(a.nodes_per_level, b.nodes_per_level);
  EXPECT_EQ(a.shift, b.shift);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a.cube_min[k], b.cube_min[k]);
}

// The oracles that need no reference.
void expect_valid(const PointHierarchy& h, const PointColumns& input) {
  ASSERT_FALSE(h.nodes.empty());
  EXPECT_EQ(h.nodes[0].code, 1u);
  auto cell_code = [&](uint64_t p) {
    uint32_t c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = h.cell(p, a);
    uint64_t code = 0;
    for (int i = 0; i < 21; ++i)
      for (int a = 0; a < 3; ++a) code |= uint64_t{(c[a] >> i) & 1} << (3 * i + a);
    return code;
  };
  std::multiset<std::tuple<int32_t, int32_t, int32_t>> at_leaves, in;
  for (uint64_t i = 0; i < input.size(); ++i) in.insert({input.xyz[3 * i], input.xyz[3 * i + 1], input.xyz[3 * i + 2]});
  uint64_t leaf_points = 0;
  // Each node's points lie in its cell, and an inner node's representatives are points of its leaves below.
  std::vector<uint64_t> parent(h.nodes.size(), 0);
  for (size_t i = 0; i < h.nodes.size(); ++i) {
    const PointNode& n = h.nodes[i];
    const uint32_t level = n.level;
    EXPECT_EQ(uint64_t{1} << (3 * level), n.code & ~((uint64_t{1} << (3 * level)) - 1)) << "sentinel of node " << i;
    const uint64_t prefix = n.code ^ (uint64_t{1} << (3 * level));
    for (uint64_t p = n.first_point; p < n.first_point + n.point_count; ++p) {
      ASSERT_EQ(cell_code(p) >> (3 * (21 - level)), prefix) << "point " << p << " outside node " << i;
      if (n.leaf()) at_leaves.insert({h.points.xyz[3 * p], h.points.xyz[3 * p + 1], h.points.xyz[3 * p + 2]});
    }
    if (n.leaf()) {
      leaf_points += n.point_count;
      EXPECT_EQ(n.point_count, n.subtree_points);
    } else {
      uint64_t sum = 0;
      uint32_t c = n.first_child;
      for (uint32_t o = 0; o < 8; ++o) {
        if (!(n.child_mask >> o & 1)) continue;
        ASSERT_LT(c, h.nodes.size());
        EXPECT_EQ(h.nodes[c].code, (n.code << 3) | o) << "child " << o << " of node " << i;
        parent[c] = i;
        sum += h.nodes[c].subtree_points;
        ++c;
      }
      EXPECT_EQ(sum, n.subtree_points) << "node " << i;
      EXPECT_LE(n.point_count, n.subtree_points);
    }
  }
  EXPECT_EQ(leaf_points, input.size());
  // A representative is a copy (every attribute) of a leaf point; lying in its node's cell, which the cells of
  // the nodes below partition, that point is in the node's subtree.
  std::vector<std::array<int64_t, 10>> leaves;
  for (const PointNode& n : h.nodes)
    if (n.leaf())
      for (uint64_t p = n.first_point; p < n.first_point + n.point_count; ++p) leaves.push_back(record(h.points, p));
  std::sort(leaves.begin(), leaves.end());
  for (size_t i = 0; i < h.nodes.size(); ++i) {
    const PointNode& n = h.nodes[i];
    if (n.leaf()) continue;
    for (uint64_t p = n.first_point; p < n.first_point + n.point_count; ++p)
      ASSERT_TRUE(std::binary_search(leaves.begin(), leaves.end(), record(h.points, p)))
          << "representative " << p << " of node " << i << " is no copy of a leaf point";
  }
  EXPECT_TRUE(at_leaves == in) << "the leaves do not hold every input point exactly once";
}

}  // namespace mv::test
