// The conservative voxelizer against an independent exact count: every candidate cell tested with the
// separating-axis theorem over the 13 axes in exact rational arithmetic (GMP), written here without any code
// shared with the kernels (kernels/common/tri_box.h evaluates the same theorem in double). The kernel's
// double evaluation may only differ on near-ties: the test reports the differences and requires them to stay
// within 0.05 % of the voxels (none are expected).
#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cstdio>

#include "reference.h"
#include "megavox/voxelize.h"
#include "test_support.h"

namespace mv::test {
std::vector<float> test_triangles(uint32_t n, uint64_t seed);  // test_voxelize.cpp

namespace {

using Vec = std::array<mpq_class, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
mpq_class dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Does the closed cell [c, c+1]^3 meet the triangle? Separating-axis theorem, exact.
bool exact_overlap(const std::array<Vec, 3>& v, const std::array<uint32_t, 3>& c) {
  const Vec lo = {mpq_class(c[0]), mpq_class(c[1]), mpq_class(c[2])};
  const Vec e[3] = {sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])};
  std::vector<Vec> axes = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, cross(e[0], e[1])};
  for (const Vec& edge : e)
    for (int a = 0; a < 3; ++a) {
      Vec unit = {0, 0, 0};
      unit[a] = 1;
      axes.push_back(cross(unit, edge));
    }
  for (const Vec& ax : axes) {
    mpq_class t0 = dot(v[0], ax), t1 = dot(v[1], ax), t2 = dot(v[2], ax);
    mpq_class tmin = std::min({t0, t1, t2}), tmax = std::max({t0, t1, t2});
    // the cell's projection: its corner lo plus the positive parts of the axis
    mpq_class bmin = dot(lo, ax), bmax = bmin;
    for (int a = 0; a < 3; ++a) (ax[a] > 0 ? bmax : bmin) += ax[a];
    if (tmax < bmin || tmin > bmax) return false;
  }
  return true;
}

std::vector<uint64_t> exact_voxels(const std::vector<float>& tris, uint32_t n) {
  std::vector<uint64_t> keys;
  for (size_t t = 0; t + 9 <= tris.size(); t += 9) {
    std::array<Vec, 3> v;
    for (int p = 0; p < 3; ++p)
      for (int a = 0; a < 3; ++a) v[p][a] = mpq_class(double(tris[t + 3 * p + a]));
    uint32_t lo[3], hi[3];
    float mn[3];
    for (int a = 0; a < 3; ++a) {
      mn[a] = std::min({tris[t + a], tris[t + 3 + a], tris[t + 6 + a]});
      float mx = std::max({tris[t + a], tris[t + 3 + a], tris[t + 6 + a]});
      lo[a] = mn[a] <= 0 ? 0 : std::min<uint32_t>(n - 1, uint32_t(mn[a]));
      hi[a] = mx <= 0 ? 0 : std::min<uint32_t>(n - 1, uint32_t(mx));
      if (lo[a] > 0 && float(lo[a]) == mn[a]) --lo[a];  // a cell touched at its top face is a candidate too
    }
    for (uint32_t x = lo[0]; x <= hi[0]; ++x)
      for (uint32_t y = lo[1]; y <= hi[1]; ++y)
        for (uint32_t z = lo[2]; z <= hi[2]; ++z) {
          const uint32_t c[3] = {x, y, z};
          // half-open cells: a triangle lying wholly at or above a cell's upper face (not the grid's top)
          // belongs to the cells above
          bool above = false;
          for (int a = 0; a < 3; ++a) above = above || (c[a] + 1 < n && mn[a] >= float(c[a] + 1));
          if (!above && exact_overlap(v, {x, y, z})) keys.push_back(ref::morton3(x, y, z, 21));
        }
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

// The device's conservative voxels of `tris` (grid units, n voxels per axis) against the exact count.
void expect_exact_count(Device& dev, const std::string& name, const std::vector<float>& tris, uint32_t n) {
  const std::vector<uint64_t> exact = exact_voxels(tris, n);
  Voxelizer vox(dev, n);
  vox.add(tris);
  std::vector<uint64_t> got = vox.take_keys(), diff;
  std::set_symmetric_difference(got.begin(), got.end(), exact.begin(), exact.end(), std::back_inserter(diff));
  std::printf("%s: %zu voxels, exact count %zu, %zu differ\n", name.c_str(), got.size(), exact.size(), diff.size());
  EXPECT_LE(double(diff.size()), 0.0005 * double(exact.size())) << name;
}

class ConservativeVoxelizationTest : public ::testing::TestWithParam<DeviceInfo> {};

// Random triangles (large ones too, hence the small grid) and a closed solid.
TEST_P(ConservativeVoxelizationTest, MatchesAnExactRationalCount) {
  expect_exact_count(shared_device(GetParam()), "random", test_triangles(16, 21), 16);
  expect_exact_count(shared_device(GetParam()), "octahedron", octahedron_grid_triangles(64), 64);
}

TEST_P(ConservativeVoxelizationTest, SharedMeshesMatchAnExactRationalCount) {
  const char* meshes[] = {"meshes_stanford/bunny_npm_small.ply", "meshes_misc/fandisk.ply"};
  for (const char* mesh : meshes) MV_SKIP_WITHOUT_SHARED_DATA(mesh);
  for (const char* mesh : meshes)
    expect_exact_count(shared_device(GetParam()), mesh,
                       mesh_grid_triangles(shared_data_file(mesh), 64, parse_grid_origin("min")), 64);
}

MV_INSTANTIATE_ON_ALL_DEVICES(ConservativeVoxelizationTest);

}  // namespace
}  // namespace mv::test
