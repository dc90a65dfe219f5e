// The two voxelization rules and the grid placements: the thin (6-separating) rule against a brute force
// written from its definition, thin within conservative on real meshes, both rules invariant under moves by
// whole voxels, and the min / center / explicit-cube grids.
#include <algorithm>
#include <cmath>
#include <random>

#include "reference.h"
#include "common/voxelize.h"
#include "megavox/error.h"
#include "megavox/voxelize.h"
#include "test_support.h"

namespace mv::test {
std::vector<float> test_triangles(uint32_t n, uint64_t seed);  // test_voxelize.cpp

namespace {

// The thin rule from its statement, independently of kernels/common/tri_thin.h: the plane meets the line
// through the voxel centre along the normal's dominant axis within [c - 1/2, c + 1/2) (closed at the grid's
// top), and in every projection with a non-zero normal component some corner of the L1 ball of radius 1/2
// lies inside each (oriented) edge's half-plane; candidates are the cells meeting the triangle's bounding
// box, half-open.
bool thin_brute_force(const float* t, uint32_t i, uint32_t j, uint32_t k, uint32_t n) {
  const double c[3] = {i + 0.5, j + 0.5, k + 0.5};
  const uint32_t cell[3] = {i, j, k};
  double v[3][3];
  for (int p = 0; p < 3; ++p)
    for (int a = 0; a < 3; ++a) v[p][a] = t[3 * p + a];
  for (int a = 0; a < 3; ++a) {
    double lo = std::min({v[0][a], v[1][a], v[2][a]}), hi = std::max({v[0][a], v[1][a], v[2][a]});
    if (cell[a] > hi || (cell[a] + 1 <= lo && cell[a] + 1 < n)) return false;
  }
  double e0[3], e1[3], nrm[3];
  for (int a = 0; a < 3; ++a) e0[a] = v[1][a] - v[0][a], e1[a] = v[2][a] - v[1][a];
  nrm[0] = e0[1] * e1[2] - e0[2] * e1[1];
  nrm[1] = e0[2] * e1[0] - e0[0] * e1[2];
  nrm[2] = e0[0] * e1[1] - e0[1] * e1[0];
  int d = 2;
  if (std::abs(nrm[1]) > std::abs(nrm[2])) d = 1;
  if (std::abs(nrm[0]) > std::abs(nrm[d])) d = 0;
  if (nrm[d] == 0) return false;
  double dot = 0;
  for (int a = 0; a < 3; ++a) dot += nrm[a] * (v[0][a] - c[a]);
  double s = dot / nrm[d];  // the plane's crossing of the centre line, relative to c[d]
  if (s < -0.5 || (s >= 0.5 && !(s == 0.5 && cell[d] + 1 == n))) return false;
  for (int a = 0; a < 3; ++a) {
    if (nrm[a] == 0) continue;
    int u = (a + 1) % 3, w = (a + 2) % 3;
    double sign = nrm[a] > 0 ? 1 : -1;
    for (int e = 0; e < 3; ++e) {
      const double* p = v[e];
      const double* q = v[(e + 1) % 3];
      double nu = -(q[w] - p[w]) * sign, nw = (q[u] - p[u]) * sign;
      const double corner[4][2] = {{c[u] + 0.5, c[w]}, {c[u] - 0.5, c[w]}, {c[u], c[w] + 0.5}, {c[u], c[w] - 0.5}};
      bool inside = false;
      for (auto& x : corner) inside = inside || nu * (x[0] - p[u]) + nw * (x[1] - p[w]) >= 0;
      if (!inside) return false;
    }
  }
  return true;
}

TEST(ThinRule, SingleTrianglesMatchTheBruteForce) {
  std::mt19937 rng(11);
  const uint32_t n = 16;
  std::uniform_real_distribution<float> pos(0.0f, float(n));
  std::uniform_real_distribution<float> near(-3.0f, 3.0f);
  for (int t = 0; t < 400; ++t) {
    float tri[9];
    for (int a = 0; a < 3; ++a) tri[a] = pos(rng);
    for (int p = 1; p < 3; ++p)
      for (int a = 0; a < 3; ++a) tri[3 * p + a] = std::clamp(tri[a] + (t % 2 ? 4 : 1) * near(rng), 0.0f, float(n));
    std::vector<uint64_t> expect;
    for (uint32_t x = 0; x < n; ++x)
      for (uint32_t y = 0; y < n; ++y)
        for (uint32_t z = 0; z < n; ++z)
          if (thin_brute_force(tri, x, y, z, n)) expect.push_back(ref::morton3(x, y, z, 21));
    std::sort(expect.begin(), expect.end());
    EXPECT_EQ(ref::voxelize(std::vector<float>(tri, tri + 9), n, true), expect) << "triangle " << t;
  }
}

TEST(ThinRule, AxisAlignedTriangleIsOneLayerThick) {
  // In the plane z = 2.5 (the centres' plane) and in z = 2 (a grid plane): one layer, the voxel above.
  for (float z : {2.5f, 2.0f}) {
    auto keys = ref::voxelize({0.2f, 0.2f, z, 3.8f, 0.2f, z, 0.2f, 3.8f, z}, 8, true);
    ASSERT_FALSE(keys.empty());
    for (uint64_t k : keys) EXPECT_EQ(ref::morton3(0, 0, 2, 21), k & ref::morton3(0, 0, 0x1fffff, 21)) << z;
  }
  // On the grid's top face: the last layer.
  auto top = ref::voxelize({0.2f, 0.2f, 8.0f, 3.8f, 0.2f, 8.0f, 0.2f, 3.8f, 8.0f}, 8, true);
  ASSERT_FALSE(top.empty());
  for (uint64_t k : top) EXPECT_EQ(ref::morton3(0, 0, 7, 21), k & ref::morton3(0, 0, 0x1fffff, 21));
}

// On `tris` (grid units, n voxels per axis) the thin rule sets a subset of the conservative voxels: fewer, but
// more than a quarter.
void expect_thin_within_conservative(Device& dev, const std::string& name, const std::vector<float>& tris,
                                     uint32_t n) {
  Voxelizer cons(dev, n), thin(dev, n, Voxelizer::Rule::kThin);
  cons.add(tris);
  thin.add(tris);
  auto c = cons.take_keys(), t = thin.take_keys();
  EXPECT_TRUE(std::includes(c.begin(), c.end(), t.begin(), t.end())) << name;
  EXPECT_LT(t.size(), c.size()) << name;
  EXPECT_GT(t.size(), c.size() / 4) << name;
}

class ThinRuleTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(ThinRuleTest, WithinConservativeAndThinner) {
  Device& dev = shared_device(GetParam());
  expect_thin_within_conservative(dev, "octahedron", octahedron_grid_triangles(128), 128);
  expect_thin_within_conservative(dev, "random", test_triangles(64, 7), 64);
}

TEST_P(ThinRuleTest, SharedMeshesWithinConservativeAndThinner) {
  const char* meshes[] = {"meshes_stanford/bunny_npm_small.ply", "meshes_misc/fandisk.ply", "meshes_misc/spot.ply"};
  for (const char* mesh : meshes) MV_SKIP_WITHOUT_SHARED_DATA(mesh);
  for (const char* mesh : meshes)
    expect_thin_within_conservative(shared_device(GetParam()), mesh,
                                    mesh_grid_triangles(shared_data_file(mesh), 256, parse_grid_origin("min")), 256);
}

MV_INSTANTIATE_ON_ALL_DEVICES(ThinRuleTest);

TEST(VoxelRules, MovingByWholeVoxelsMovesTheVoxels) {
  // Vertices on a 1/64 lattice, so adding whole voxels is exact in float.
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pos(0, 40 * 64);
  std::vector<float> tris, moved;
  const int dx = 5, dy = 17, dz = 9;
  for (int t = 0; t < 300; ++t) {
    int ax = pos(rng), ay = pos(rng), az = pos(rng);
    for (int p = 0; p < 3; ++p) {
      int x = p ? std::clamp(ax + pos(rng) / 16 - 80, 0, 40 * 64) : ax;
      int y = p ? std::clamp(ay + pos(rng) / 16 - 80, 0, 40 * 64) : ay;
      int z = p ? std::clamp(az + pos(rng) / 16 - 80, 0, 40 * 64) : az;
      tris.insert(tris.end(), {x / 64.0f, y / 64.0f, z / 64.0f});
      moved.insert(moved.end(), {x / 64.0f + dx, y / 64.0f + dy, z / 64.0f + dz});
    }
  }
  for (bool thin : {false, true}) {
    auto a = ref::voxelize(tris, 64, thin), b = ref::voxelize(moved, 64, thin);
    std::vector<uint64_t> shifted;
    for (uint64_t k : a) {
      uint32_t x = 0, y = 0, z = 0;
      for (int i = 0; i < 21; ++i) {
        x |= uint32_t((k >> (3 * i)) & 1) << i;
        y |= uint32_t((k >> (3 * i + 1)) & 1) << i;
        z |= uint32_t((k >> (3 * i + 2)) & 1) << i;
      }
      shifted.push_back(ref::morton3(x + dx, y + dy, z + dz, 21));
    }
    std::sort(shifted.begin(), shifted.end());
    EXPECT_EQ(shifted, b) << (thin ? "thin" : "conservative");
  }
}

TEST(Grid, MinCornerCubeOnTheLongestExtent) {
  Bounds b;
  b.extend(1, 2, 3);
  b.extend(11, 6, 5);
  GridTransform g = grid_for_bounds(b, 1024, parse_grid_origin("min"));
  EXPECT_DOUBLE_EQ(g.voxel_size, 10.0 / 1024);
  EXPECT_DOUBLE_EQ(g.origin[0], 1);
  EXPECT_DOUBLE_EQ(g.origin[1], 2);
  EXPECT_DOUBLE_EQ(g.origin[2], 3);
  std::vector<float> pos = {1, 2, 3, 11, 6, 5, 6, 4, 4};
  uint32_t idx[3] = {0, 1, 2};
  std::vector<float> grid;
  triangles_to_grid(g, pos, idx, 1, grid);
  EXPECT_FLOAT_EQ(grid[3], 1024.0f);
  EXPECT_FLOAT_EQ(grid[4], 409.6f);
  EXPECT_FLOAT_EQ(grid[5], 204.8f);
  EXPECT_THROW(parse_grid_origin("corner"), Error);
}

TEST(Grid, ExplicitCubeSharedByInputsAndCutAtItsFaces) {
  GridPlacement p = parse_grid_bounds("-1,-1,-1,2");
  GridTransform g = grid_for_bounds(Bounds{}, 8, p);  // the model's bounds do not matter
  EXPECT_DOUBLE_EQ(g.origin[0], -1);
  EXPECT_DOUBLE_EQ(g.voxel_size, 0.25);
  // One triangle half outside (kept, unclamped), one fully outside (dropped).
  std::vector<float> pos = {0, 0, 0, 3, 0, 0, 0, 0.5f, 0, 5, 5, 5, 6, 5, 5, 5, 6, 5};
  uint32_t idx[6] = {0, 1, 2, 3, 4, 5};
  std::vector<float> grid;
  triangles_to_grid(g, pos, idx, 2, grid, true);
  ASSERT_EQ(grid.size(), 9u);
  EXPECT_FLOAT_EQ(grid[3], 16.0f);
  auto keys = ref::voxelize(grid, 8);
  for (uint64_t k : keys) EXPECT_LT(k, uint64_t{512});  // all inside the 8^3 grid
  EXPECT_FALSE(keys.empty());
  for (const char* bad : {"1,2,3", "1,2,3,0", "1,2,3,-4", "a,b,c,d", "1,2,3,4,5", "1,2,3,nan"})
    EXPECT_THROW(parse_grid_bounds(bad), Error) << bad;
}

}  // namespace
}  // namespace mv::test
