// Triangle buckets of the out-of-core build: spilling to disk gives every cube the same triangles.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

#include "voxel/triangle_buckets.h"

namespace mv::test {
namespace {

using Tri = std::array<float, 9>;

std::vector<Tri> sorted_triangles(const std::vector<float>& floats) {
  std::vector<Tri> out(floats.size() / 9);
  for (size_t t = 0; t < out.size(); ++t) std::copy_n(floats.begin() + 9 * t, 9, out[t].begin());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(TriangleBuckets, SpillingKeepsEveryCubesTriangles) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> at(-2.0f, 66.0f), step(-6.0f, 6.0f);  // some outside, some spanning cubes
  const uint32_t per_axis = 4, cube = 16;
  TriangleBuckets held(per_axis, cube, uint64_t{1} << 30), spilled(per_axis, cube, 1000);
  for (int batch = 0; batch < 20; ++batch) {
    std::vector<float> tris;
    for (int t = 0; t < 300; ++t) {
      const float x = at(rng), y = at(rng), z = at(rng);
      for (int v = 0; v < 3; ++v) tris.insert(tris.end(), {x + step(rng), y + step(rng), z + step(rng)});
    }
    held.add(tris);
    spilled.add(tris);
  }
  EXPECT_EQ(held.spilled_bytes(), 0u);
  EXPECT_GT(spilled.spilled_bytes(), 0u);
  size_t total = 0;
  for (uint32_t z = 0; z < per_axis; ++z)
    for (uint32_t y = 0; y < per_axis; ++y)
      for (uint32_t x = 0; x < per_axis; ++x) {
        std::vector<Tri> a = sorted_triangles(held.take(x, y, z)), b = sorted_triangles(spilled.take(x, y, z));
        EXPECT_TRUE(a == b) << "cube " << x << "," << y << "," << z;
        EXPECT_TRUE(sorted_triangles(spilled.take(x, y, z)).empty());  // taking empties the bucket
        total += a.size();
      }
  EXPECT_GE(total, 20u * 300u);  // every triangle lands in at least one cube (clamped at the edges)
}

}  // namespace
}  // namespace mv::test
