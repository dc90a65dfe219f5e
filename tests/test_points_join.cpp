// A point build over ranks, without MPI: a sorted stream cut at cells of the top level into parts, each part's
// subtrees built up to that level, then joined and finished as rank 0 does (points/point_ranks.cpp), gives the
// nodes and node order of one builder over the whole stream; and the deal of cells to ranks.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "megavox/rank_collectives.h"
#include "points/omicron.h"
#include "points/point_kernels.h"
#include "test_support.h"

namespace mv {
namespace {

using test::shared_device;

class PointsJoinTest : public ::testing::TestWithParam<DeviceInfo> {};

// Sorted codes of a cloud: a sheet with dense spots and exact repeats, so leaves collapse at several levels.
std::vector<uint64_t> sorted_codes(Device& dev, uint64_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<int32_t> xyz;
  for (uint64_t i = 0; i < n; ++i) {
    const double a = u(rng), b = u(rng);
    const bool spot = (i % 5) == 0;
    xyz.insert(xyz.end(), {static_cast<int32_t>((spot ? 0.3 + 0.01 * a : a) * 60000),
                           static_cast<int32_t>((spot ? 0.6 + 0.01 * b : b) * 60000),
                           static_cast<int32_t>(3000 * std::sin(a * 7) * std::cos(b * 5)) + (i % 97 == 0 ? 0 : 1)});
  }
  const points::PointCube cube = points::cube_of(xyz);
  std::vector<uint64_t> codes;
  std::vector<uint32_t> index;
  points::point_codes(dev, xyz, cube, codes, index);
  std::sort(codes.begin(), codes.end());
  return codes;
}

struct Built {
  std::vector<PointNode> nodes;
  std::vector<uint64_t> per_level, order;
};

Built assembled(const points::OmicronBuilder& b) {
  Built out;
  std::vector<points::NodePoints> sources;
  b.assemble(out.nodes, sources, out.per_level);
  points::expand_order(sources, b.reps(), out.order);
  return out;
}

void expect_same(const Built& a, const Built& b, const std::string& what) {
  ASSERT_EQ(a.per_level, b.per_level) << what;
  ASSERT_EQ(a.nodes.size(), b.nodes.size()) << what;
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].code, b.nodes[i].code) << what << " node " << i;
    EXPECT_EQ(a.nodes[i].first_point, b.nodes[i].first_point) << what << " node " << i;
    EXPECT_EQ(a.nodes[i].point_count, b.nodes[i].point_count) << what << " node " << i;
    EXPECT_EQ(a.nodes[i].subtree_points, b.nodes[i].subtree_points) << what << " node " << i;
    EXPECT_EQ(a.nodes[i].first_child, b.nodes[i].first_child) << what << " node " << i;
    EXPECT_EQ(a.nodes[i].child_mask, b.nodes[i].child_mask) << what << " node " << i;
  }
  EXPECT_EQ(a.order, b.order) << what;
}

TEST_P(PointsJoinTest, PartsJoinedAreOneBuild) {
  Device& dev = shared_device(GetParam());
  const std::vector<uint64_t> codes = sorted_codes(dev, 30000, 3);
  for (uint32_t max_points : {40u, 300u, 5000u}) {
    points::OmicronRule rule{7, max_points, 6};
    points::OmicronBuilder one(dev, rule);
    one.concatenate(codes, true);
    const Built whole = assembled(one);
    std::mt19937_64 rng(max_points);
    for (uint32_t top = 1; top <= rule.depth; ++top) {
      for (int parts : {1, 2, 3, 7}) {
        // cuts at random cells of the top level; parts may be empty
        const uint32_t shift = 3 * (21 - top);
        std::vector<uint64_t> cuts{0, codes.size()};
        for (int k = 1; k < parts; ++k) {
          const uint64_t cell = codes[rng() % codes.size()] >> shift;
          cuts.push_back(std::lower_bound(codes.begin(), codes.end(), cell << shift) - codes.begin());
        }
        std::sort(cuts.begin(), cuts.end());
        points::OmicronRule joined_rule = rule;
        points::OmicronBuilder joined(dev, joined_rule);
        for (size_t k = 0; k + 1 < cuts.size(); ++k) {
          points::OmicronRule part_rule = rule;
          part_rule.top_level = top;
          points::OmicronBuilder part(dev, part_rule);
          part.concatenate(std::span<const uint64_t>(codes.data() + cuts[k], cuts[k + 1] - cuts[k]), true);
          joined.join(part.take_part(), cuts[k]);
        }
        joined.finish_join(codes);
        expect_same(whole, assembled(joined),
                    "max " + std::to_string(max_points) + ", top " + std::to_string(top) + ", parts " + std::to_string(parts));
      }
    }
  }
}

TEST_P(PointsJoinTest, RefusesPartsThatDoNotFit) {
  Device& dev = shared_device(GetParam());
  const std::vector<uint64_t> codes = sorted_codes(dev, 2000, 4);
  points::OmicronRule rule{5, 100, 6};
  rule.top_level = 2;
  points::OmicronBuilder part(dev, rule);
  part.concatenate(codes, true);
  rule.top_level = 0;
  points::OmicronBuilder joined(dev, rule);
  EXPECT_THROW(joined.join(part.take_part(), 5), Error);  // the first part starts at point 0
}

TEST(RankDeal, ContiguousRangesOfEqualWeight) {
  EXPECT_EQ(deal_in_order({1, 1, 1, 1}, 2), (std::vector<int>{0, 0, 1, 1}));
  EXPECT_EQ(deal_in_order({0, 0, 0}, 3), (std::vector<int>{0, 0, 0}));
  EXPECT_EQ(deal_in_order({10, 0, 0, 1}, 3), (std::vector<int>{0, 2, 2, 2}));
  const std::vector<int> owner = deal_in_order(std::vector<uint64_t>(1000, 7), 5);
  for (int r = 0; r < 5; ++r) EXPECT_EQ(std::count(owner.begin(), owner.end(), r), 200);
  EXPECT_TRUE(std::is_sorted(owner.begin(), owner.end()));
}

MV_INSTANTIATE_ON_ALL_DEVICES(PointsJoinTest);

}  // namespace
}  // namespace mv
