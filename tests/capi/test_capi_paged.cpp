// C API scenes larger than their device budget: a paged .mvx opened through mvOpenScene on a device whose
// memory= is an eighth of the DAG answers mvTraceRays with the resident scene's bytes, streaming pages and
// staying inside the budget; cache_memory= streams every encoding the same way; mvRenderScene converges.
#include <cstring>
#include <random>
#include <vector>

#include "megavox/build.h"
#include "megavox/megavox.h"
#include "megavox/megavox.hpp"
#include "megavox/mvx.h"
#include "megavox/trace.h"
#include "capi_fixture.h"
#include "test_support.h"
#include "option_words.h"

namespace mv::test::capi {
namespace {

class CApiPagedTest : public ::testing::TestWithParam<DeviceInfo> {};

// Random triangles (seeded): a surface whose DAG merges little, so every encoding spans many pages.
Mesh triangle_soup(size_t triangles, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> at(-1, 1), near(-0.2f, 0.2f);
  Mesh m;
  for (size_t t = 0; t < triangles; ++t) {
    const float c[3] = {at(rng), at(rng), at(rng)};
    for (int v = 0; v < 3; ++v) {
      for (int a = 0; a < 3; ++a) m.positions.push_back(c[a] + near(rng));
      m.indices.push_back(static_cast<uint32_t>(3 * t + v));
    }
  }
  return m;
}

// `m` built at `resolution` as `format`, written paged in pages of `page_words` words.
std::string paged_mesh(const DeviceInfo& info, const Mesh& m, const char* format, uint32_t resolution,
                       uint32_t page_words) {
  const std::string ply = temp_path("paged_mesh.ply"), built = temp_path("paged_built.mvx"),
                    out = temp_path(std::string("paged_") + format + "_" + std::to_string(resolution) + ".mvx");
  write_ply(ply, m.positions, m.indices);
  BuildOptions o;
  o.input = ply;
  o.output = built;
  o.resolution = resolution;
  o.encoding = parse_encoding(format);
  build_mvx(shared_device(info), o);
  write_mvx(out, read_mvx(built), MvxPaging{page_words, NodeOrder::subtree});
  return out;
}

std::vector<MvTraceHit> trace_all(MvDevice device, MvScene scene, const std::vector<MvTraceRay>& rays) {
  std::vector<MvTraceHit> hits(rays.size());
  EXPECT_EQ(mvTraceRays(scene, rays.data(), hits.data(), rays.size(), nullptr), MV_ERROR_NONE)
      << mvGetDeviceLastErrorMessage(device);
  return hits;
}

MvSceneStats stats_of(MvScene scene) {
  MvSceneStats s{};
  s.byteSize = sizeof s;
  EXPECT_EQ(mvGetSceneStats(scene, &s), MV_ERROR_NONE);
  return s;
}

TEST_P(CApiPagedTest, ASceneEightTimesTheBudgetAnswersAsTheResidentOne) {
  static const std::string path = paged_mesh(GetParam(), octahedron(), "svo", 2048, 1024);  // the same bytes on every device
  const uint64_t dag_bytes = open_paged_mvx(path).words * 4;
  ASSERT_GT(dag_bytes, uint64_t{32} << 20);
  CDevice big(GetParam());
  MvScene resident = mvOpenScene(big.handle, path.c_str());
  ASSERT_TRUE(resident) << mvGetDeviceLastErrorMessage(big.handle);
  MvSceneInfo info;
  ASSERT_EQ(mvGetSceneInfo(resident, &info), MV_ERROR_NONE);
  const std::vector<MvTraceRay> rays = random_rays(info, 20000, 5);
  const std::vector<MvTraceHit> want = trace_all(big.handle, resident, rays);
  EXPECT_EQ(stats_of(resident).paged, 0u);

  const uint64_t budget = dag_bytes / 8;
  CDevice small(GetParam(), "memory=" + std::to_string(budget));
  MvScene paged = mvOpenScene(small.handle, path.c_str());
  ASSERT_TRUE(paged) << mvGetDeviceLastErrorMessage(small.handle);
  const std::vector<MvTraceHit> got = trace_all(small.handle, paged, rays);
  ASSERT_EQ(std::memcmp(got.data(), want.data(), got.size() * sizeof(MvTraceHit)), 0);
  const MvSceneStats s = stats_of(paged);
  EXPECT_EQ(s.paged, 1u);
  EXPECT_GT(s.pagesStreamed, 0u);
  EXPECT_GT(s.passes, 1u);
  EXPECT_GT(s.peakDeviceBytes, 0u);
  EXPECT_LE(s.peakDeviceBytes, budget);
  EXPECT_LT(s.cacheBytes, dag_bytes / 8);

  // a picture through the cache converges to the resident one's
  MvRenderArguments r;
  mvInitRenderArguments(&r);
  r.width = 64;
  r.height = 48;
  r.aoSamples = 0;
  std::vector<uint8_t> a(64 * 48 * 4), b(a.size());
  ASSERT_EQ(mvRenderScene(resident, nullptr, &r, a.data(), 0), MV_ERROR_NONE);
  ASSERT_EQ(mvRenderScene(paged, nullptr, &r, b.data(), 0), MV_ERROR_NONE) << mvGetDeviceLastErrorMessage(small.handle);
  EXPECT_EQ(a, b);
  EXPECT_LE(stats_of(paged).peakDeviceBytes, budget);
  mvReleaseScene(paged);
  mvReleaseScene(resident);
}

TEST_P(CApiPagedTest, CacheMemoryStreamsEveryEncodingExactly) {
  CDevice big(GetParam());
  CDevice cached(GetParam(), "cache_memory=64K");  // 256 pages of 64 words
  const Mesh soup = triangle_soup(2000, 17);
  for (const char* format : {"svo", "svdag", "ussvdag", "ssvdag"}) {
    SCOPED_TRACE(format);
    const std::string path = paged_mesh(GetParam(), soup, format, 256, 64);
    ASSERT_GT(open_paged_mvx(path).words, 65536u / 4 * 2);  // twice the cache
    MvScene resident = mvOpenScene(big.handle, path.c_str());
    MvScene paged = mvOpenScene(cached.handle, path.c_str());
    ASSERT_TRUE(resident && paged);
    MvSceneInfo info;
    ASSERT_EQ(mvGetSceneInfo(paged, &info), MV_ERROR_NONE);
    const std::vector<MvTraceRay> rays = random_rays(info, 2000, 9);
    const std::vector<MvTraceHit> want = trace_all(big.handle, resident, rays), got = trace_all(cached.handle, paged, rays);
    EXPECT_EQ(std::memcmp(got.data(), want.data(), got.size() * sizeof(MvTraceHit)), 0);
    const MvSceneStats s = stats_of(paged);
    EXPECT_EQ(s.paged, 1u);
    EXPECT_EQ(s.cacheBytes, 65536u);
    EXPECT_GT(s.pagesStreamed, 0u);
    mvReleaseScene(paged);
    mvReleaseScene(resident);
  }
  MvSceneStats bad{};
  EXPECT_EQ(mvGetSceneStats(nullptr, &bad), MV_ERROR_INVALID_ARGUMENT);
  // the C++ layer: the same figures
  megavox::Device cpp("device=" + GetParam().selector() + ",cache_memory=64K");
  const megavox::Scene scene = cpp.open(paged_mesh(GetParam(), triangle_soup(2000, 17), "svdag", 256, 64));
  EXPECT_EQ(scene.stats().paged, 0u);  // nothing traced yet
  const std::vector<MvTraceRay> rays = random_rays(scene.info(), 100, 2);
  scene.trace(rays);
  EXPECT_EQ(scene.stats().paged, 1u);
  EXPECT_GT(scene.stats().pagesStreamed, 0u);
}

MV_INSTANTIATE_ON_ALL_DEVICES(CApiPagedTest);

}  // namespace
}  // namespace mv::test::capi
