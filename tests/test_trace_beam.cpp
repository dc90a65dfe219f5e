// The beam pre-pass (kernels/common/trace_beam.h) and the restarted walk it feeds (mv_restart): a walk started
// later gives the same hit, the coarse grid marks what a plain host computation marks, every tile start is
// before each of its rays' hits (flat reference DDA), and camera rays hit the same cells with and without it,
// on every device and encoding.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "common/morton.h"
#include "common/trace_beam.h"
#include "megavox/encode.h"
#include "megavox/trace.h"
#include "render/frame.h"
#include "test_support.h"
#include "trace/host_trace.h"
#include "trace/trace_engine.h"
#include "trace_reference.h"
#include "voxel/build_steps.h"

namespace mv::test {
namespace {

// The same hit record but for the step count, which may only fall.
void expect_same_hit(const MvHit& got, const MvHit& want, const std::string& what) {
  ASSERT_EQ(got.info, want.info) << what;
  ASSERT_EQ(MV_FBITS(got.t), MV_FBITS(want.t)) << what;
  ASSERT_EQ(got.x, want.x) << what;
  ASSERT_EQ(got.y, want.y) << what;
  ASSERT_EQ(got.z, want.z) << what;
  ASSERT_LE(got.steps, want.steps) << what;
}

// Rays in root-cube units: from outside toward a point inside, from inside, along boundary planes and through
// cell corners (simultaneous crossings), with and without a level-of-detail offset.
std::vector<MvRay> restart_rays(uint32_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), sym(-1.0f, 1.0f);
  auto grid_plane = [&] { return float(rng() % (n + 1)) / float(n); };
  std::vector<MvRay> rays;
  for (int i = 0; i < 1200; ++i) {
    std::array<float, 3> o, d;
    const int kind = i % 4;
    for (int a = 0; a < 3; ++a) {
      o[a] = kind == 1 ? unit(rng) : 0.5f + sym(rng) * 1.5f;
      d[a] = kind == 1 ? sym(rng) : unit(rng) - o[a];
    }
    if (kind == 2) o[i % 3] = grid_plane(), d[i % 3] = 0.0f;        // within a boundary plane
    if (kind == 3)                                                 // through cell corners
      for (int a = 0; a < 3; ++a) o[a] = grid_plane() - 2.0f * (d[a] = rng() % 2 ? 0.25f : -0.25f);
    rays.push_back(MvRay{o[0], o[1], o[2], d[0], d[1], d[2], 1e30f, (i % 5) * 0.05f});
  }
  return rays;
}

class BeamTest : public ::testing::TestWithParam<DeviceInfo> {};

// The kernel's own walk built for the host (the DAG built on each device).
TEST_P(BeamTest, AWalkStartedBeforeTheHitEndsAtTheSameHit) {
  const uint32_t levels = 6;
  Device& dev = shared_device(GetParam());
  for (auto& [name, voxels] : voxel_sets(levels))
    for (Encoding e : kEncodings) {
      SCOPED_TRACE(name + ", " + encoding_name(e));
      HostTracer host(unit_grid_file(dev, voxels, levels, e).dag);
      const std::vector<MvRay> rays = restart_rays(1u << levels, 5);
      uint64_t restarts = 0;
      for (float proj : {0.0f, 40.0f})
        for (size_t i = 0; i < rays.size(); ++i) {
          const MvHit want = host.trace(rays[i], proj, 60000);
          const bool hit = MV_INFO_STATUS(want.info) == MV_TRACE_HIT;
          if (hit && want.t <= 0) continue;  // a hit at t = 0: no later start is allowed
          for (float u : {0.05f, 0.3f, 0.6f, 0.9f, 0.999f, 1.0f}) {
            // before the hit (the float just below it at u = 1); a miss: anywhere, past the cube too
            const float start = hit ? (u < 1 ? want.t * u : std::nextafter(want.t, 0.0f)) : u * 4;
            if (!(start > 0)) continue;
            const MvHit got = host.trace(rays[i], proj, 60000, start);
            ASSERT_NO_FATAL_FAILURE(expect_same_hit(got, want, "ray " + std::to_string(i) + " start " +
                                                                   std::to_string(start) + " proj " + std::to_string(proj)));
            restarts += got.steps < want.steps;
          }
        }
      if (name != "one voxel") EXPECT_GT(restarts, 100u);
    }
}

// The frames the tests take: the model framed from outside (iso and front), a close view with the eye inside
// the cube, a grazing one, with and without the level of detail; sizes that are not whole tiles.
struct BeamView {
  Camera camera;
  RenderOptions options;
};

std::vector<BeamView> beam_views(uint32_t n) {
  Bounds b;
  for (int a = 0; a < 3; ++a) b.lo[a] = 0, b.hi[a] = n;
  std::vector<BeamView> views;
  for (const char* v : {"iso", "front"})
    for (double lod : {0.0, 1.0}) {
      BeamView x{view_camera(b, v, 45), {}};
      x.options.width = 203;
      x.options.height = 117;
      x.options.lod_pixels = lod;
      views.push_back(x);
    }
  BeamView inside{view_camera(b, "iso", 60), {}};
  for (int a = 0; a < 3; ++a) inside.camera.eye[a] = 0.45 * n, inside.camera.target[a] = n;
  inside.options.width = 96;
  inside.options.height = 61;
  views.push_back(inside);
  BeamView grazing = inside;
  grazing.camera.eye[0] = -0.5 * n, grazing.camera.eye[1] = 0.5 * n, grazing.camera.eye[2] = 0.5 * n;
  grazing.camera.target[0] = n, grazing.camera.target[1] = 0.49 * n, grazing.camera.target[2] = 0.51 * n;
  grazing.camera.fov = 20;
  views.push_back(grazing);
  return views;
}

// The dilated grid against a plain computation from the voxels: a cell of side S is full when a voxel lies in
// it, and marked when it or a neighbour is full (the border cells outside the cube included).
TEST_P(BeamTest, TheGridMarksEveryCellBesideAFullOne) {
  Device& dev = shared_device(GetParam());
  const uint32_t levels = 6, n = 1u << levels;
  for (auto& [name, voxels] : voxel_sets(levels))
    for (Encoding e : {Encoding::svdag, Encoding::ssvdag})
      for (uint32_t g : {4u, 16u, 64u}) {
        SCOPED_TRACE(name + ", " + encoding_name(e) + ", " + std::to_string(g) + " cells");
        const MvxFile file = unit_grid_file(dev, voxels, levels, e);
        TraceEngine engine(dev, file.dag);
        const uint32_t m = g + 2, rn = mv_beam_row_words(m);
        std::vector<uint32_t> got(m * m * rn);
        dev.download(engine.beam_grid(g), got.data(), got.size() * 4);
        std::vector<uint8_t> full(g * g * g, 0);
        for (uint64_t k : voxels) {
          uint32_t c[3];
          for (uint32_t a = 0; a < 3; ++a) c[a] = mv_morton3_64_axis(k, a) * g / n;
          full[(c[2] * g + c[1]) * g + c[0]] = 1;
        }
        for (uint32_t z = 0; z < m; ++z)
          for (uint32_t y = 0; y < m; ++y)
            for (uint32_t x = 0; x < m; ++x) {
              bool want = false;
              for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                  for (int dx = -1; dx <= 1; ++dx) {
                    const int cx = int(x) - 1 + dx, cy = int(y) - 1 + dy, cz = int(z) - 1 + dz;
                    if (cx >= 0 && cy >= 0 && cz >= 0 && cx < int(g) && cy < int(g) && cz < int(g))
                      want = want || full[(cz * g + cy) * g + cx];
                  }
              const bool marked = (got[(z * m + y) * rn + x / 32] >> (x % 32)) & 1;
              ASSERT_EQ(marked, want) << "cell " << x << "," << y << "," << z;
            }
      }
}

// Each tile's start against the flat reference DDA: every ray of the tile hits nothing before it (and a tile
// marked empty has no ray that hits); then the device's camera rays with the beam give the hit records they
// give without it (all but the step count), every encoding, and some rays start late.
TEST_P(BeamTest, CameraRaysHitWhatTheyHitWithoutIt) {
  Device& dev = shared_device(GetParam());
  const uint32_t levels = 6, n = 1u << levels;
  GridTransform grid;
  grid.resolution = n;
  uint32_t with_parent = 0;
  for (auto& [name, voxels] : voxel_sets(levels)) {
    ref::Occupancy occ(voxels, levels);
    for (Encoding e : kEncodings) {
      const MvxFile file = unit_grid_file(dev, voxels, levels, e);
      TraceEngine engine(dev, file.dag);
      uint32_t view_no = 0;
      for (const BeamView& v : beam_views(n)) {
        SCOPED_TRACE(name + ", " + encoding_name(e) + ", view " + std::to_string(view_no++));
        const FrameSetup s = frame_setup(grid, levels, v.camera, v.options);
        const BeamSetup beam = beam_setup(s, TraceEngine::kBeamMaxCells);
        ASSERT_GE(beam.cells, 4u);
        const uint32_t px = s.width * s.height;
        const uint64_t floats = TraceEngine::beam_camera_floats(s.width, s.height);
        Buffer cam = dev.alloc(floats * 4, "camera");
        dev.upload(cam, s.camera, sizeof s.camera);
        // with and without the parent pass over tiles twice as wide: each start a proof
        engine.beam(cam, s.width, s.height, beam.cells, beam.reach, view_no % 2 ? 0 : beam.parent_cells,
                    beam.parent_reach, s.proj);
        with_parent += view_no % 2 == 0 && beam.parent_cells;
        std::vector<float> starts(floats);
        dev.download(cam, starts.data(), starts.size() * 4);
        std::vector<uint32_t> with(px * MV_HIT_WORDS), without(px * MV_HIT_WORDS);
        Buffer hits = dev.alloc(with.size() * 4, "hits");
        engine.trace(nullptr, &cam, 0, px, s.width, s.proj, 60000, false, hits, true);
        dev.download(hits, with.data(), with.size() * 4);
        engine.trace(nullptr, &cam, 0, px, s.width, s.proj, 60000, false, hits, false);
        dev.download(hits, without.data(), without.size() * 4);
        uint64_t fewer = 0, nothing = 0;
        for (uint32_t i = 0; i < px; ++i) {
          const MvHit a = mv_load_hit(with.data(), i), b = mv_load_hit(without.data(), i);
          const float start = starts[MV_CAMERA_FLOATS + mv_beam_tile(i, s.width)];
          const MvHit r = ref::trace(occ, mv_camera_ray(s.camera, i, s.width), s.proj);
          if (MV_INFO_STATUS(r.info) == MV_TRACE_HIT) {
            ASSERT_LT(start, MV_BEAM_NOTHING) << "pixel " << i;
            if (r.t > 0) ASSERT_LT(start, r.t) << "pixel " << i;
            else ASSERT_LE(start, 0.0f) << "pixel " << i;  // the eye in a full voxel
          }
          ASSERT_NO_FATAL_FAILURE(expect_same_hit(a, b, "pixel " + std::to_string(i)));
          fewer += a.steps < b.steps;
          nothing += start >= MV_BEAM_NOTHING;
        }
        // (random voxels and the tiled pattern fill every coarse cell of the framed views)
        if (name == "shell" || name == "one voxel") EXPECT_GT(fewer, 0u);
        if (view_no <= 4) EXPECT_GT(nothing, 0u);    // framed from outside: some tiles see nothing
      }
    }
  }
  EXPECT_GT(with_parent, 0u);
}

TEST_P(BeamTest, BadGridsAreRefused) {
  Device& dev = shared_device(GetParam());
  const MvxFile file = unit_grid_file(dev, voxel_sets(6).front().second, 6, Encoding::svdag);
  TraceEngine engine(dev, file.dag);
  Buffer cam = dev.alloc(4096, "camera");
  EXPECT_THROW(engine.beam(cam, 16, 16, 3, 0.01f, 0, 0, 0), Error);
  EXPECT_THROW(engine.beam(cam, 16, 16, 128, 0.01f, 0, 0, 0), Error);
  EXPECT_THROW(engine.beam(cam, 16, 16, 8, 0.0f, 0, 0, 0), Error);
  EXPECT_THROW(engine.beam(cam, 16, 16, 8, 0.01f, 6, 0.02f, 0), Error);
}

MV_INSTANTIATE_ON_ALL_DEVICES(BeamTest);

}  // namespace
}  // namespace mv::test
