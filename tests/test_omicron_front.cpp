// OMiCroN's rendering front (host/core/points/omicron_front.h) kept over a growing OmicronBuilder, with the paper's
// invariants checked after every step: spans in Morton order and covering every formed point once (2.1), no
// placeholder left whose settled leaf exists, no absorbed node drawn, every drawn inner node fine enough; and at
// the end, the finished hierarchy's leaves (no LOD) or its top-down cut (a LOD rule), on every device.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>
#include <vector>

#include "points/omicron.h"
#include "points/omicron_front.h"
#include "test_support.h"

namespace mv {
namespace {

using points::FrontEntry;
using points::LodNode;
using points::OmicronBuilder;
using points::OmicronFront;

class OmicronFrontTest : public ::testing::TestWithParam<DeviceInfo> {};

constexpr uint32_t kDepth = 7;

// Sorted 63-bit Morton codes: a few dense clusters (inner nodes with representatives) over a sparse spread
// (leaves that collapse), duplicates included.
std::vector<uint64_t> sorted_codes(uint64_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint64_t> codes;
  const uint64_t mask = (uint64_t{1} << 63) - 1;
  uint64_t centre[4];
  for (uint64_t& c : centre) c = rng() & mask;
  for (uint64_t i = 0; i < n; ++i) {
    if (i % 3 == 0) codes.push_back(rng() & mask);
    else codes.push_back((centre[i % 4] & ~((uint64_t{1} << 42) - 1)) | (rng() & ((uint64_t{1} << 42) - 1)));
  }
  std::sort(codes.begin(), codes.end());
  return codes;
}

const LodNode* find(const OmicronBuilder& b, uint32_t level, uint64_t prefix, uint64_t* at = nullptr) {
  const auto& list = b.level(level);
  auto it = std::lower_bound(list.begin(), list.end(), prefix, [](const LodNode& n, uint64_t p) { return n.prefix < p; });
  if (it == list.end() || it->prefix != prefix) return nullptr;
  if (at) *at = static_cast<uint64_t>(it - list.begin());
  return &*it;
}

void expect_invariants(const OmicronBuilder& b, const OmicronFront& f, const OmicronFront::FineEnough& fine) {
  uint64_t covered = 0, next_span = 0;
  for (const FrontEntry& e : f.entries()) {
    const LodNode& n = b.level(e.level)[e.at];
    const uint32_t shift = 3 * (kDepth - e.level);
    ASSERT_GE(n.prefix << shift, next_span) << "spans in Morton order, disjoint";
    next_span = (n.prefix + 1) << shift;
    covered += n.points;
    if (e.placeholder) {
      ASSERT_EQ(e.level, kDepth);
      // Not settled: without a parent yet, or absorbed into a collapsed leaf that has no parent yet.
      uint32_t l = e.level;
      uint64_t at = e.at, prefix = n.prefix;
      while (at < b.first_root(l) && b.level(l)[at].absorbed) {
        --l;
        prefix >>= 3;
        ASSERT_NE(find(b, l, prefix, &at), nullptr);
      }
      ASSERT_TRUE(at >= b.first_root(l) || b.level(l)[at].child_mask != 0) << "a settled leaf left as a placeholder";
    } else {
      ASSERT_FALSE(n.absorbed) << "an absorbed node in the front";
      if (n.child_mask != 0) {
        ASSERT_TRUE(fine(e.level, n.prefix)) << "an inner node too coarse, not branched";
      }
    }
  }
  EXPECT_EQ(covered, b.formed()) << "the front covers every formed point once";
}

// The finished hierarchy's top-down cut with the same rule, as (level, prefix) in Morton order.
std::vector<std::pair<uint32_t, uint64_t>> top_down_cut(const std::vector<PointNode>& nodes,
                                                        const OmicronFront::FineEnough& fine) {
  std::vector<std::pair<uint32_t, uint64_t>> cut;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const PointNode& n = nodes[stack.back()];
    stack.pop_back();
    const uint64_t prefix = n.code ^ (uint64_t{1} << (3 * n.level));
    if (n.leaf() || fine(n.level, prefix)) {
      cut.emplace_back(n.level, prefix);
      continue;
    }
    for (uint32_t k = n.first_child + static_cast<uint32_t>(__builtin_popcount(n.child_mask)); k > n.first_child;)
      stack.push_back(--k);
  }
  return cut;
}

TEST_P(OmicronFrontTest, InvariantsHoldAfterEveryStepAndTheEndIsTheCut) {
  Device& dev = test::shared_device(GetParam());
  const std::vector<uint64_t> codes = sorted_codes(60000, 5);
  using Rule = std::tuple<const char*, OmicronFront::FineEnough>;
  const Rule rules[] = {
      {"leaves only", [](uint32_t, uint64_t) { return false; }},
      {"level 3 and below", [](uint32_t level, uint64_t) { return level >= 3; }},
      // Uneven: finer towards high codes, so prune and branch both happen as the cut advances.
      {"uneven", [](uint32_t level, uint64_t prefix) {
         return level > 0 && level >= 2 + ((prefix >> (3 * level - 3)) & 3);  // by the level-1 ancestor's octant
       }}};
  for (const auto& [name, fine] : rules) {
    SCOPED_TRACE(name);
    points::OmicronRule rule;
    rule.depth = kDepth;
    rule.max_node_points = 200;
    rule.grid_bits = 2;
    OmicronBuilder b(dev, rule);
    OmicronFront f(b);
    for (uint64_t end = 1500;; end = std::min<uint64_t>(end + 1500, codes.size())) {
      b.concatenate(std::span<const uint64_t>(codes.data(), end), end == codes.size());
      f.update(fine);
      expect_invariants(b, f, fine);
      if (HasFatalFailure() || end == codes.size()) break;
    }
    std::vector<PointNode> nodes;
    std::vector<points::NodePoints> sources;
    std::vector<uint64_t> per_level;
    b.assemble(nodes, sources, per_level);
    std::vector<std::pair<uint32_t, uint64_t>> front;
    for (const FrontEntry& e : f.entries()) {
      EXPECT_FALSE(e.placeholder);
      front.emplace_back(e.level, b.level(e.level)[e.at].prefix);
    }
    EXPECT_EQ(front, top_down_cut(nodes, fine));
    EXPECT_GT(f.stats().substituted, 0u);
    if (std::string(name) != "leaves only") {
      EXPECT_GT(f.stats().pruned, 0u);
    }
    // The points a frame draws: a leaf's run, an inner node's representatives.
    std::vector<uint64_t> drawn;
    for (const FrontEntry& e : f.entries()) f.append_points(e, drawn);
    if (std::string(name) == "leaves only") EXPECT_EQ(drawn.size(), codes.size());
    else EXPECT_LT(drawn.size(), codes.size());
  }
}

TEST_P(OmicronFrontTest, ATinyCloudEndsAsItsRootLeaf) {
  Device& dev = test::shared_device(GetParam());
  const std::vector<uint64_t> codes = sorted_codes(50, 9);
  points::OmicronRule rule;
  rule.depth = 4;
  rule.max_node_points = 1000;
  OmicronBuilder b(dev, rule);
  OmicronFront f(b);
  b.concatenate(codes, true);
  f.update([](uint32_t, uint64_t) { return false; });
  ASSERT_EQ(f.entries().size(), 1u);
  EXPECT_EQ(f.entries()[0].level, 0u);
  EXPECT_FALSE(f.entries()[0].placeholder);
}

MV_INSTANTIATE_ON_ALL_DEVICES(OmicronFrontTest);

}  // namespace
}  // namespace mv
