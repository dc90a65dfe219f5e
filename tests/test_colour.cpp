// Voxel colours from point clouds on every device against plain loops (host/ref/colour_reference.h): the voxel
// set, every node's colour in depth-first order, the attribute index recovered from subtree sizes on SVDAGs and
// SSVDAGs, and edge cases (one point, one voxel, ties at one half, all channels at 255).
#include <random>

#include "colour_reference.h"
#include "megavox/colour.h"
#include "megavox/dag.h"
#include "common/colour.h"
#include "test_support.h"

namespace mv::test {
namespace {

class ColourTest : public ::testing::TestWithParam<DeviceInfo> {};

struct ColourCloud {
  std::vector<uint32_t> cells, rgb;
};

// n points in a 2^levels grid, clumped into `spread` cells per axis around a few centres so voxels hold several.
ColourCloud random_colour_cloud(size_t n, uint32_t levels, uint32_t spread, uint64_t seed) {
  std::mt19937_64 rng(seed);
  const uint32_t side = 1u << levels;
  ColourCloud c;
  uint32_t centre[3] = {};
  for (size_t p = 0; p < n; ++p) {
    if (p % 64 == 0)
      for (auto& a : centre) a = static_cast<uint32_t>(rng() % side);
    for (uint32_t a : centre) c.cells.push_back(std::min<uint32_t>(side - 1, a + static_cast<uint32_t>(rng() % spread)));
    c.rgb.push_back(static_cast<uint32_t>(rng() & 0xffffff));
  }
  return c;
}

std::vector<uint8_t> reference_bytes(const std::vector<ref::ColourNode>& nodes) {
  std::vector<uint8_t> out;
  for (const auto& n : nodes) out.insert(out.end(), n.rgb, n.rgb + 3);
  return out;
}

void check_colour_cloud(Device& dev, const ColourCloud& c, uint32_t levels, const std::string& what) {
  SCOPED_TRACE(what);
  const CloudVoxels got = voxelize_cloud(dev, c.cells, c.rgb, levels);
  EXPECT_EQ(got.keys, ref::cloud_voxel_keys(c.cells));
  const std::vector<ref::ColourNode> want = ref::preorder_colours(c.cells, c.rgb, levels);
  ASSERT_EQ(got.colours.size(), want.size() * 3);
  EXPECT_EQ(got.colours, reference_bytes(want));
  const CloudVoxels wide = voxelize_cloud(dev, c.cells, c.rgb, levels, nullptr, ColourSums::wide);
  EXPECT_EQ(wide.colours, got.colours) << "64-bit prefix sums";
  const CloudVoxels plain = voxelize_cloud(dev, c.cells, {}, levels);
  EXPECT_EQ(plain.keys, got.keys);
  EXPECT_TRUE(plain.colours.empty());
}

TEST_P(ColourTest, RandomCloudsMatchTheReference) {
  Device& dev = shared_device(GetParam());
  uint64_t seed = 1;
  for (uint32_t levels : {1u, 3u, 6u, 10u})
    for (size_t n : {size_t{1}, size_t{7}, size_t{500}, size_t{20000}})
      for (uint32_t spread : {1u, 3u, 40u})
        check_colour_cloud(dev, random_colour_cloud(n, levels, spread, ++seed), levels,
                           "levels " + std::to_string(levels) + ", points " + std::to_string(n) + ", spread " +
                               std::to_string(spread));
}

// The mean (a float quotient made exact in integers) against sum / count rounded half up in 128 bits, for small
// counts, counts past 2^32 and at that seam.
TEST(ColourMean, BothWidthsRoundHalfUp) {
  std::mt19937_64 rng(5);
  auto want = [](uint64_t sum, uint64_t count) {
    return static_cast<uint32_t>((2 * static_cast<unsigned __int128>(sum) + count) / (2 * static_cast<unsigned __int128>(count)));
  };
  for (int i = 0; i < 200000; ++i) {
    const int shape = i % 4;
    uint64_t count = shape == 0 ? 1 + rng() % 1000 : shape == 1 ? 1 + (rng() >> 33) : 1 + (rng() >> 8) % (uint64_t{1} << 40);
    if (shape == 3) count = (uint64_t{1} << 32) - 1 + rng() % 3;  // at the seam
    const uint64_t sum = count * (rng() % 256) + rng() % count;      // a mean of 8-bit values
    ASSERT_EQ(mv_colour_mean(sum, count), want(sum, count)) << sum << " / " << count;
  }
}

TEST_P(ColourTest, EdgeCases) {
  Device& dev = shared_device(GetParam());
  // One point.
  check_colour_cloud(dev, {{5, 0, 7}, {0x123456}}, 3, "one point");
  // Every point in one voxel, many of them: sums far past 8 bits.
  ColourCloud one = random_colour_cloud(70000, 5, 1, 3);
  for (size_t p = 0; p < one.cells.size(); ++p) one.cells[p] = 17;
  check_colour_cloud(dev, one, 5, "one voxel");
  // Means of exactly one half round up; 255 stays 255; 0 stays 0.
  check_colour_cloud(dev, {{0, 0, 0, 0, 0, 0}, {0x000000, 0x01ff01}}, 2, "half up");
  check_colour_cloud(dev, {{0, 0, 0, 3, 3, 3, 1, 2, 3}, {0xffffff, 0xffffff, 0x000000}}, 2, "extremes");
  // Two voxels whose own means tie at one half in their parent: (1 + 2) / 2 = 1.5 -> 2.
  check_colour_cloud(dev, {{0, 0, 0, 1, 0, 0}, {0x010101, 0x020202}}, 4, "inner tie");
  // The deepest grid: 21 levels, cells at both ends.
  check_colour_cloud(dev, {{0, 0, 0, (1u << 21) - 1, (1u << 21) - 1, (1u << 21) - 1, 0, 0, 0}, {1, 2, 3}}, 21,
                     "21 levels");
}

// The attribute index each traversal recovers from subtree sizes is the node's place in a plain pre-order
// walk, on SVDAGs and on SSVDAGs (whose mirrored pointers show children in another order than stored).
TEST_P(ColourTest, IndicesFromSubtreeSizesArePreorder) {
  Device& dev = shared_device(GetParam());
  uint64_t seed = 100;
  for (uint32_t levels : {3u, 5u, 7u})
    for (uint32_t spread : {2u, 9u}) {
      ColourCloud c = random_colour_cloud(3000, levels, spread, ++seed);
      // Mirror images of one clump, so the SSVDAG shares subtrees under reflections.
      const uint32_t side = 1u << levels;
      const size_t n = c.rgb.size();
      for (size_t p = 0; p < n; ++p) {
        c.cells.insert(c.cells.end(), {side - 1 - c.cells[3 * p], c.cells[3 * p + 1], side - 1 - c.cells[3 * p + 2]});
        c.rgb.push_back(c.rgb[p]);
      }
      const CloudVoxels v = voxelize_cloud(dev, c.cells, c.rgb, levels);
      const std::vector<ref::ColourNode> want = ref::preorder_colours(c.cells, c.rgb, levels);
      for (bool symmetric : {false, true}) {
        SCOPED_TRACE(std::string(symmetric ? "ssvdag" : "svdag") + ", levels " + std::to_string(levels));
        const Dag dag = symmetric ? build_ssvdag(dev, v.keys, levels) : build_svdag(dev, v.keys, levels);
        ASSERT_EQ(subtree_sizes(dag)[levels][0], want.size());
        if (symmetric) {  // the walk must have met mirrored pointers to show anything
          uint64_t mirrored = 0;
          for (uint32_t l = 2; l <= levels; ++l)
            for (uint32_t t : dag.level[l].tags) mirrored += t != 0;
          EXPECT_GT(mirrored, 0u);
        }
        std::vector<uint64_t> order;
        bool same = true;
        for_each_attribute_index(dag, [&](uint64_t index, uint32_t level, uint64_t code) {
          order.push_back(index);
          same = same && index < want.size() && want[index].level == level && want[index].code == code &&
                 std::equal(want[index].rgb, want[index].rgb + 3, v.colours.begin() + 3 * index);
        });
        EXPECT_TRUE(same);
        ASSERT_EQ(order.size(), want.size());
        for (size_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], i) << "pre-order position " << i;
      }
    }
}

MV_INSTANTIATE_ON_ALL_DEVICES(ColourTest);

}  // namespace
}  // namespace mv::test
