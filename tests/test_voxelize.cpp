// Surface voxelization: the decisive predicate on hand-made cases, then the kernel on every device against
// the CPU reference (which tests every voxel of each triangle's bounding box with the same predicate).
#include <algorithm>
#include <random>

#include "reference.h"
#include "common/voxelize.h"
#include "megavox/voxelize.h"
#include "megavox/error.h"
#include "test_support.h"

namespace mv::test {
namespace {

using Tri = std::array<float, 9>;

std::vector<uint64_t> keys_of(std::initializer_list<std::array<uint32_t, 3>> voxels) {
  std::vector<uint64_t> k;
  for (auto& v : voxels) k.push_back(ref::morton3(v[0], v[1], v[2], 21));
  std::sort(k.begin(), k.end());
  return k;
}

std::vector<float> flat(std::initializer_list<Tri> tris) {
  std::vector<float> out;
  for (auto& t : tris) out.insert(out.end(), t.begin(), t.end());
  return out;
}

TEST(VoxelPredicate, TriangleInsideOneVoxel) {
  EXPECT_EQ(ref::voxelize(flat({{1.2f, 1.2f, 1.5f, 1.8f, 1.3f, 1.5f, 1.4f, 1.7f, 1.5f}}), 8), keys_of({{1, 1, 1}}));
}

TEST(VoxelPredicate, TriangleOnAGridPlaneBelongsToTheVoxelAboveIt) {
  // In the plane z = 2: voxels [2, 3) in z only, never the layer below (half-open cells).
  auto keys = ref::voxelize(flat({{0.5f, 0.5f, 2.0f, 2.5f, 0.5f, 2.0f, 0.5f, 2.5f, 2.0f}}), 8);
  ASSERT_FALSE(keys.empty());
  for (uint64_t k : keys) EXPECT_EQ(ref::morton3(0, 0, 2, 21), k & ref::morton3(0, 0, 0x1fffff, 21)) << k;
}

TEST(VoxelPredicate, TopFaceBelongsToTheLastVoxel) {
  auto keys = ref::voxelize(flat({{0.5f, 0.5f, 8.0f, 1.5f, 0.5f, 8.0f, 0.5f, 1.5f, 8.0f}}), 8);
  EXPECT_EQ(keys, keys_of({{0, 0, 7}, {1, 0, 7}, {0, 1, 7}, {1, 1, 7}}));
}

TEST(VoxelPredicate, SeparatedByAnEdgeAxis) {
  // Near voxel (0,0,0)'s corner but cut off by the triangle's edge: the bounding boxes overlap, the
  // triangle does not reach the voxel.
  float t[9] = {1.1f, 0.0f, 0.5f, 2.0f, 0.0f, 0.5f, 2.0f, 1.9f, 0.5f};
  EXPECT_FALSE(mv_voxel_hit(t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7], t[8], 0, 0, 0, 8, 0));
  EXPECT_TRUE(mv_voxel_hit(t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7], t[8], 1, 0, 0, 8, 0));
}

// Every point sampled on a triangle lies in a voxel the reference reports (conservative coverage).
TEST(VoxelPredicate, CoversSampledPoints) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 31.9f);
  for (int t = 0; t < 200; ++t) {
    Tri tri;
    for (auto& c : tri) c = u(rng);
    auto keys = ref::voxelize(flat({tri}), 32);
    for (int a = 0; a <= 20; ++a)
      for (int b = 0; a + b <= 20; ++b) {
        double wa = a / 20.0, wb = b / 20.0, wc = 1 - wa - wb;
        uint32_t v[3];
        for (int ax = 0; ax < 3; ++ax) {
          double p = wa * tri[ax] + wb * tri[3 + ax] + wc * tri[6 + ax];
          v[ax] = std::min<uint32_t>(31, static_cast<uint32_t>(p));
        }
        uint64_t k = ref::morton3(v[0], v[1], v[2], 21);
        // a sample within rounding of a cell face may fall on either side; accept the neighbour
        bool found = std::binary_search(keys.begin(), keys.end(), k);
        if (!found) {
          for (int ax = 0; ax < 3 && !found; ++ax) {
            double p = wa * tri[ax] + wb * tri[3 + ax] + wc * tri[6 + ax];
            if (std::abs(p - std::round(p)) < 1e-4) {
              uint32_t w[3] = {v[0], v[1], v[2]};
              w[ax] = w[ax] > 0 ? w[ax] - 1 : 0;
              found = std::binary_search(keys.begin(), keys.end(), ref::morton3(w[0], w[1], w[2], 21));
            }
          }
        }
        ASSERT_TRUE(found) << "triangle " << t << " sample " << a << "," << b;
      }
  }
}

// Triangles of every kind the kernels must get exactly right.
}  // namespace

std::vector<float> test_triangles(uint32_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> pos(0.0f, float(n));
  std::uniform_real_distribution<float> small(-2.0f, 2.0f);
  std::uniform_int_distribution<int> cell(0, int(n));
  std::vector<float> out;
  auto push = [&](std::initializer_list<float> t) { out.insert(out.end(), t.begin(), t.end()); };
  for (int i = 0; i < 300; ++i) {  // small triangles
    float x = pos(rng), y = pos(rng), z = pos(rng);
    push({x, y, z, std::clamp(x + small(rng), 0.f, float(n)), std::clamp(y + small(rng), 0.f, float(n)),
          std::clamp(z + small(rng), 0.f, float(n)), std::clamp(x + small(rng), 0.f, float(n)),
          std::clamp(y + small(rng), 0.f, float(n)), std::clamp(z + small(rng), 0.f, float(n))});
  }
  // large triangles only on small grids: the reference tests every voxel of their bounding boxes
  for (int i = 0; i < (n <= 64 ? 20 : 0); ++i)
    push({pos(rng), pos(rng), pos(rng), pos(rng), pos(rng), pos(rng), pos(rng), pos(rng), pos(rng)});
  for (int i = 0; i < 30; ++i) {  // axis-aligned, vertices on grid lines: the exact boundary cases
    float a = float(cell(rng)), b = float(cell(rng)), c = float(cell(rng)), d = float(cell(rng)), e = float(cell(rng));
    push({a, b, c, a, d, c, a, b, e});
    push({b, a, c, d, a, c, b, a, e});
    push({b, c, a, d, c, a, b, e, a});
  }
  if (n <= 64) push({0, 0, 0, float(n), 0, 0, 0, float(n), float(n)});      // spans the grid
  push({1.5f, 1.5f, 1.5f, 1.5f, 1.5f, 1.5f, 1.5f, 1.5f, 1.5f});              // a point
  push({1.0f, 2.0f, 3.0f, 5.0f, 6.0f, 7.0f, 3.0f, 4.0f, 5.0f});              // collinear
  push({float(n), float(n), float(n), float(n), 0, float(n), 0, float(n), float(n)});  // on the top faces
  return out;
}

namespace {

class VoxelizeTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(VoxelizeTest, MatchesReference) {
  Device& dev = shared_device(GetParam());
  for (uint32_t n : {16u, 64u, 1024u}) {
    std::vector<float> tris = test_triangles(n, n);
    for (bool thin : {false, true}) {
      Voxelizer v(dev, n, thin ? Voxelizer::Rule::kThin : Voxelizer::Rule::kConservative);
      v.add(tris);
      std::vector<uint64_t> got = v.take_keys();
      std::vector<uint64_t> expect = ref::voxelize(tris, n, thin);
      ASSERT_EQ(got.size(), expect.size()) << "grid " << n << (thin ? " thin" : " conservative");
      ASSERT_TRUE(got == expect) << "grid " << n << (thin ? " thin" : " conservative");
    }
  }
}

TEST_P(VoxelizeTest, SmallBudgetEmitsInChunksWithTheSameResult) {
  auto dev = Device::open({GetParam().selector(), 4u << 20, false});
  std::vector<float> tris = test_triangles(64, 3);
  for (int rep = 0; rep < 6; ++rep) tris.insert(tris.end(), tris.begin(), tris.begin() + 9 * 30);
  Voxelizer v(*dev, 64);
  v.add(std::vector<float>(tris.begin(), tris.begin() + 9 * 200));  // two batches as well
  v.add(std::vector<float>(tris.begin() + 9 * 200, tris.end()));
  EXPECT_TRUE(v.take_keys() == ref::voxelize(tris, 64));
}

TEST(Grid, CentredCubeOnTheLongestExtent) {
  Bounds b;
  b.extend(0, 0, 0);
  b.extend(10, 4, 2);
  GridTransform g = grid_for_bounds(b, 1024);
  EXPECT_DOUBLE_EQ(g.voxel_size, 10.0 / 1024);
  EXPECT_DOUBLE_EQ(g.origin[0], 0);
  EXPECT_DOUBLE_EQ(g.origin[1], -3);
  EXPECT_DOUBLE_EQ(g.origin[2], -4);
  std::vector<float> pos = {0, 0, 0, 10, 4, 2, 5, 2, 1};
  uint32_t idx[3] = {0, 1, 2};
  std::vector<float> grid;
  triangles_to_grid(g, pos, idx, 1, grid);
  EXPECT_FLOAT_EQ(grid[0], 0.0f);
  EXPECT_FLOAT_EQ(grid[3], 1024.0f);  // the top face: the last voxel
  EXPECT_FLOAT_EQ(grid[4], 716.8f);
  EXPECT_THROW(grid_for_bounds(b, 0), Error);
  EXPECT_THROW(grid_for_bounds(Bounds{}, 16), Error);
  uint32_t bad[3] = {0, 1, 7};
  EXPECT_THROW(triangles_to_grid(g, pos, bad, 1, grid), Error);
}

MV_INSTANTIATE_ON_ALL_DEVICES(VoxelizeTest);

}  // namespace
}  // namespace mv::test
