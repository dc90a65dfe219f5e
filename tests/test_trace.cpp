// Ray traversal: every encoding on every device against the flat voxel-by-voxel reference DDA.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "reference.h"
#include "common/morton.h"
#include "trace_reference.h"
#include "trace/trace_engine.h"
#include "megavox/dag.h"
#include "megavox/encode.h"
#include "megavox/error.h"
#include "megavox/trace.h"
#include "voxel/build_steps.h"
#include "test_support.h"

namespace mv::test {
namespace {

// Rays of every kind the issue names, in grid units of an n^3 grid: from outside toward the grid, from
// inside, axis-parallel (on and off voxel boundaries), grazing along boundary planes, diagonal through
// voxel corners (simultaneous crossings), away from the grid, from inside full voxels, with short tmax.
std::vector<Ray> test_rays(const std::vector<uint64_t>& voxels, uint32_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
  const float fn = float(n);
  auto in_grid = [&] { return std::array<float, 3>{unit(rng) * fn, unit(rng) * fn, unit(rng) * fn}; };
  auto integer = [&] { return float(rng() % (n + 1)); };
  std::vector<Ray> rays;
  auto add = [&](std::array<float, 3> o, std::array<float, 3> d, float tmax = INFINITY) {
    Ray r;
    for (int a = 0; a < 3; ++a) {
      r.origin[a] = o[a];
      r.direction[a] = d[a];
    }
    r.tmax = tmax;
    rays.push_back(r);
  };
  for (int i = 0; i < 300; ++i) {  // outside, aimed at a point inside
    std::array<float, 3> o, t = in_grid(), d;
    for (int a = 0; a < 3; ++a) o[a] = fn * 0.5f + sym(rng) * fn * 1.5f;
    for (int a = 0; a < 3; ++a) d[a] = t[a] - o[a];
    add(o, d);
  }
  for (int i = 0; i < 200; ++i) add(in_grid(), {sym(rng), sym(rng), sym(rng)});  // inside
  for (int i = 0; i < 200; ++i) {  // axis-parallel, half of them on voxel boundaries
    std::array<float, 3> o = in_grid(), d = {0, 0, 0};
    if (i % 2) o = {integer(), integer(), integer()};
    int a = i % 3;
    o[a] = (i / 3) % 2 ? -2.0f : fn + 2.0f;
    d[a] = (i / 3) % 2 ? 1.0f : -1.0f;
    add(o, d);
  }
  for (int i = 0; i < 200; ++i) {  // grazing: in a boundary plane, moving within it
    std::array<float, 3> o = in_grid(), d = {sym(rng), sym(rng), sym(rng)};
    int a = i % 3;
    o[a] = integer();
    d[a] = 0.0f;
    add(o, d);
  }
  for (int i = 0; i < 200; ++i) {  // diagonals through voxel corners
    std::array<float, 3> o = {integer(), integer(), integer()}, d;
    for (int a = 0; a < 3; ++a) d[a] = rng() % 2 ? 1.0f : -1.0f;
    if (i % 4 == 0) d[rng() % 3] *= 2.0f;
    add(o, d);
  }
  for (int i = 0; i < 100; ++i) {  // away from the grid
    std::array<float, 3> o = {-3.0f, fn * unit(rng), fn * unit(rng)};
    add(o, {-1.0f, sym(rng), sym(rng)});
  }
  for (size_t i = 0; i < std::min<size_t>(voxels.size(), 100); ++i) {  // from inside full voxels
    uint64_t k = voxels[(i * 7919) % voxels.size()];
    uint32_t c[3];
    for (uint32_t a = 0; a < 3; ++a) c[a] = mv_morton3_64_axis(k, a);
    add({c[0] + 0.5f, c[1] + 0.25f, c[2] + 0.75f}, {sym(rng), sym(rng), sym(rng)});
  }
  for (int i = 0; i < 200; ++i) {  // short tmax
    std::array<float, 3> o = in_grid();
    add(o, {sym(rng), sym(rng), sym(rng)}, unit(rng) * fn * 0.3f);
  }
  return rays;
}

// The same rays in root-cube coordinates (the grid is n unit voxels at the origin: divide by n, exact).
MvRay cube_ray(const Ray& r, uint32_t n, float lod_t = 0) {
  const float s = 1.0f / float(n);
  return MvRay{r.origin[0] * s, r.origin[1] * s, r.origin[2] * s, r.direction[0] * s, r.direction[1] * s,
               r.direction[2] * s, std::min(r.tmax, 1e30f), lod_t};
}

void expect_same(const RayHit& got, const MvHit& want, size_t i) {
  SCOPED_TRACE("ray " + std::to_string(i));
  ASSERT_FALSE(got.gave_up);
  ASSERT_EQ(got.hit, MV_INFO_STATUS(want.info) == MV_TRACE_HIT);
  if (!got.hit) return;
  EXPECT_EQ(MV_FBITS(got.t), MV_FBITS(want.t)) << got.t << " vs " << want.t;
  EXPECT_EQ(got.level, MV_INFO_LEVEL(want.info));
  EXPECT_EQ(got.cell[0], want.x);
  EXPECT_EQ(got.cell[1], want.y);
  EXPECT_EQ(got.cell[2], want.z);
  uint32_t axis = MV_INFO_AXIS(want.info);
  for (uint32_t a = 0; a < 3; ++a)
    EXPECT_EQ(got.normal[a], a == axis ? (MV_INFO_NEGATIVE(want.info) ? -1 : 1) : 0);
}

class TraceTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(TraceTest, EveryEncodingHitsWhatTheReferenceDdaHits) {
  Device& dev = shared_device(GetParam());
  for (uint32_t levels : {3u, 6u}) {
    const uint32_t n = 1u << levels;
    auto sets = voxel_sets(levels);
    sets.push_back({"octahedron", ref::voxelize(octahedron_grid_triangles(n), n)});
    for (auto& [name, voxels] : sets) {
      ref::Occupancy occ(voxels, levels);
      std::vector<Ray> rays = test_rays(voxels, n, levels * 31 + voxels.size());
      std::vector<MvHit> want;
      for (const Ray& r : rays) want.push_back(ref::trace(occ, cube_ray(r, n), 0.0f));
      size_t hits = 0;
      for (Encoding e : kEncodings) {
        SCOPED_TRACE(name + ", levels " + std::to_string(levels) + ", " + encoding_name(e));
        if (e == Encoding::ssvdag && levels < 3) continue;
        MvxFile file = unit_grid_file(dev, voxels, levels, e);
        Tracer tracer(dev, file);
        // ssvdag twice: level starts from memory, then from the parameters (both kernels on every device)
        for (int pass = 0; pass < (e == Encoding::ssvdag ? 2 : 1); ++pass) {
          SCOPED_TRACE(pass ? "level starts from the parameters" : "level starts from memory");
          if (e == Encoding::ssvdag)
            tracer.engine().set_level_starts(pass ? TraceEngine::LevelStarts::parameters
                                                  : TraceEngine::LevelStarts::memory);
          std::vector<RayHit> got = tracer.trace(rays);
          for (size_t i = 0; i < rays.size(); ++i) {
            expect_same(got[i], want[i], i);
            if (got[i].hit && got[i].level == 0) {
              EXPECT_TRUE(std::binary_search(voxels.begin(), voxels.end(),
                                             ref::morton3(got[i].cell[0], got[i].cell[1], got[i].cell[2], 21)));
            }
            hits += got[i].hit;
            if (HasFatalFailure() || HasFailure()) return;
          }
        }
      }
      EXPECT_GT(hits, 0u) << name;
    }
  }
}

// Distances: the kernel's t against the exact crossing of the hit face computed in double.
TEST_P(TraceTest, DistanceIsTheFaceCrossingWithinTolerance) {
  Device& dev = shared_device(GetParam());
  const uint32_t levels = 6, n = 64;
  auto voxels = voxel_sets(levels)[1].second;  // the shell
  MvxFile file = unit_grid_file(dev, voxels, levels, Encoding::ssvdag);
  Tracer tracer(dev, file);
  std::vector<Ray> rays = test_rays(voxels, n, 7);
  std::vector<RayHit> got = tracer.trace(rays);
  size_t checked = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const RayHit& h = got[i];
    if (!h.hit || (h.normal[0] == 0 && h.normal[1] == 0 && h.normal[2] == 0)) continue;
    int a = h.normal[0] ? 0 : h.normal[1] ? 1 : 2;
    double face = h.cell[a] + (h.normal[a] < 0 ? 0.0 : 1.0);
    double exact = (face - rays[i].origin[a]) / double(mv_dir_clamp(rays[i].direction[a]));  // 0 counts as 1e-20
    // Stated tolerance: 1e-5 of the grid side (float crossing times in the root cube) relative to |d|.
    double len = std::sqrt(double(rays[i].direction[0]) * rays[i].direction[0] +
                           double(rays[i].direction[1]) * rays[i].direction[1] +
                           double(rays[i].direction[2]) * rays[i].direction[2]);
    EXPECT_NEAR(h.t * len, exact * len, 1e-5 * n) << "ray " << i;
    ++checked;
  }
  EXPECT_GT(checked, 100u);
}

// Level of detail: with proj > 0 a ray stops at coarser full cells; kernel and reference agree.
TEST_P(TraceTest, LevelOfDetailStopsWhereTheReferenceStops) {
  Device& dev = shared_device(GetParam());
  const uint32_t levels = 6, n = 64;
  for (auto& [name, voxels] : voxel_sets(levels)) {
    ref::Occupancy occ(voxels, levels);
    std::vector<Ray> rays = test_rays(voxels, n, 11);
    std::vector<uint32_t> cube;
    std::vector<MvHit> want;
    const float proj = 40.0f;
    for (size_t i = 0; i < rays.size(); ++i) {
      MvRay r = cube_ray(rays[i], n, (i % 3) * 0.25f);
      cube.resize(cube.size() + MV_RAY_FLOATS);
      mv_store_ray(cube.data(), uint32_t(i), r);
      want.push_back(ref::trace(occ, r, proj));
    }
    for (Encoding e : kEncodings) {
      SCOPED_TRACE(name + ", " + encoding_name(e));
      MvxFile file = unit_grid_file(dev, voxels, levels, e);
      TraceEngine engine(dev, file.dag);
      Buffer rb = dev.alloc(cube.size() * 4, "rays"), hb = dev.alloc(want.size() * MV_HIT_WORDS * 4, "hits");
      dev.upload(rb, cube.data(), cube.size() * 4);
      engine.trace(&rb, nullptr, 0, uint32_t(want.size()), 0, proj, 60000, false, hb);
      std::vector<uint32_t> words(want.size() * MV_HIT_WORDS);
      dev.download(hb, words.data(), words.size() * 4);
      size_t coarse = 0;
      for (size_t i = 0; i < want.size(); ++i) {
        const MvHit got = mv_load_hit(words.data(), uint32_t(i));
        ASSERT_EQ(got.info, want[i].info) << "ray " << i;
        if (MV_INFO_STATUS(got.info) != MV_TRACE_HIT) continue;
        ASSERT_EQ(MV_FBITS(got.t), MV_FBITS(want[i].t)) << "ray " << i;
        ASSERT_EQ(got.x, want[i].x);
        ASSERT_EQ(got.y, want[i].y);
        ASSERT_EQ(got.z, want[i].z);
        coarse += MV_INFO_LEVEL(got.info) > 0;
      }
      if (name != "one voxel") {
        EXPECT_GT(coarse, 0u);
      }
    }
  }
}

// A tree deeper than the trace parameters hold level starts for (131072^3: the ssvdag kernel reads them from
// memory on every device) walks exactly like the svdag: clusters of voxels far apart, rays aimed at them.
TEST_P(TraceTest, DeepTreesWalkLikeTheSvdag) {
  Device& dev = shared_device(GetParam());
  const uint32_t levels = 17, n = 1u << levels;
  ASSERT_FALSE(mv_trace_params_hold_levels(levels, false));
  std::mt19937_64 rng(15);
  std::vector<uint64_t> voxels;
  for (int c = 0; c < 40; ++c) {  // 40 blobs of about 100 voxels
    uint32_t cx = rng() % (n - 16), cy = rng() % (n - 16), cz = rng() % (n - 16);
    for (int i = 0; i < 120; ++i) voxels.push_back(ref::morton3(cx + rng() % 8, cy + rng() % 8, cz + rng() % 8, 21));
  }
  voxels = sorted_unique(voxels);
  std::vector<Ray> rays;
  std::uniform_real_distribution<float> sym(-1.0f, 1.0f);
  for (int i = 0; i < 600; ++i) {  // from far outside or from inside the grid, toward a voxel's neighbourhood
    uint64_t k = voxels[rng() % voxels.size()];
    float t[3];
    for (uint32_t a = 0; a < 3; ++a) t[a] = mv_morton3_64_axis(k, a) + 0.5f + sym(rng) * 3.0f;
    Ray r;
    for (int a = 0; a < 3; ++a) {
      r.origin[a] = i % 2 ? t[a] + sym(rng) * 2000.0f : float(n) * (0.5f + sym(rng) * 1.2f);
      r.direction[a] = t[a] - r.origin[a];
    }
    rays.push_back(r);
  }
  MvxFile sv = unit_grid_file(dev, voxels, levels, Encoding::svdag);
  MvxFile ss = unit_grid_file(dev, voxels, levels, Encoding::ssvdag);
  std::vector<RayHit> want = Tracer(dev, sv).trace(rays), got = Tracer(dev, ss).trace(rays);
  EXPECT_THROW(Tracer(dev, ss).engine().set_level_starts(TraceEngine::LevelStarts::parameters), Error);
  size_t hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    SCOPED_TRACE("ray " + std::to_string(i));
    ASSERT_FALSE(want[i].gave_up);
    ASSERT_EQ(got[i].hit, want[i].hit);
    ASSERT_EQ(got[i].steps, want[i].steps);
    if (!want[i].hit) continue;
    ++hits;
    ASSERT_EQ(MV_FBITS(got[i].t), MV_FBITS(want[i].t));
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(got[i].cell[a], want[i].cell[a]);
      ASSERT_EQ(got[i].normal[a], want[i].normal[a]);
    }
  }
  EXPECT_GT(hits, rays.size() / 4);
}

TEST_P(TraceTest, BadRaysAreRefused) {
  Device& dev = shared_device(GetParam());
  MvxFile file = unit_grid_file(dev, voxel_sets(3)[0].second, 3, Encoding::svdag);
  Tracer tracer(dev, file);
  Ray r;
  r.origin[1] = NAN;
  EXPECT_THROW(tracer.trace({r}), Error);
  EXPECT_TRUE(tracer.trace({}).empty());
}

MV_INSTANTIATE_ON_ALL_DEVICES(TraceTest);

// The deterministic reciprocal is within a few ulps of 1 / x over the range the traversal uses.
TEST(TraceMath, ReciprocalIsAccurate) {
  std::mt19937_64 rng(5);
  for (int i = 0; i < 100000; ++i) {
    float x = std::ldexp(1.0f + float(rng() % 1000000) / 1e6f, int(rng() % 130) - 65) * (rng() % 2 ? 1 : -1);
    float r = mv_rcp(x);
    EXPECT_NEAR(double(r) * x, 1.0, 4e-7) << x;
  }
}

// The mode word keeps each field apart, and the parameters hold level starts for trees up to 64K^3 (paged: two
// words are the cache's, 16K^3).
TEST(TraceMath, ParametersPackTheirFields) {
  MvTraceParams p{};
  p.mode = MV_TRACE_MODE(21u, 1u, 0u, 31u);
  EXPECT_EQ(MV_TRACE_LEVELS(p), 21u);
  EXPECT_EQ(MV_TRACE_CAMERA(p), 1u);
  EXPECT_EQ(MV_TRACE_OCCLUSION(p), 0u);
  EXPECT_EQ(MV_TRACE_PAGE_SHIFT(p), 31u);
  p.mode = MV_TRACE_MODE(3u, 0u, 1u, 4u);
  EXPECT_EQ(MV_TRACE_LEVELS(p), 3u);
  EXPECT_EQ(MV_TRACE_CAMERA(p), 0u);
  EXPECT_EQ(MV_TRACE_OCCLUSION(p), 1u);
  EXPECT_EQ(MV_TRACE_PAGE_SHIFT(p), 4u);
  EXPECT_TRUE(mv_trace_params_hold_levels(16, false));
  EXPECT_FALSE(mv_trace_params_hold_levels(17, false));
  EXPECT_TRUE(mv_trace_params_hold_levels(14, true));
  EXPECT_FALSE(mv_trace_params_hold_levels(15, true));
  // the paged level starts lie before the cache's two words, which lie inside the parameters
  EXPECT_LE(MV_TRACE_PAGED_PARAM_LEVELS, static_cast<unsigned>(MV_TRACE_PAGE_STAMP));
  EXPECT_LT(static_cast<unsigned>(MV_TRACE_PAGE_RUNS), MV_TRACE_PARAM_LEVELS);
  EXPECT_NE(MV_TRACE_PAGE_STAMP, MV_TRACE_PAGE_RUNS);
}

}  // namespace
}  // namespace mv::test
