// Paged traversal: the trace kernel reading a paged DAG through the device page cache.
//  - one pass of the kernel equals the same code on the host over the same cache state: hits (coarse where a
//    page was missing), usage stamps and page requests;
//  - ray queries and renders converge to the resident results, byte for byte, with a cache far smaller than
//    the DAG when the view's working set fits, and renders in bands of rows when it does not;
//  - a one-page cache gives the root's level of detail, a failing producer leaves pages missing, and neither
//    ends in an error or a corrupt picture; the page table stays the inverse of the slot owners throughout.
#include <algorithm>
#include <random>

#include "cache/page_cache.h"
#include "paging/page_layout.h"
#include "paging/paged_ssvdag.h"
#include "paging/paged_stream.h"
#include "voxel/build_steps.h"
#include "reference.h"
#include "trace/trace_engine.h"
#include "common/trace.h"
#include "megavox/error.h"
#include "megavox/render.h"
#include "megavox/trace.h"
#include "test_support.h"

namespace mv::test {
namespace {

constexpr uint32_t kPageWords = 16;  // small pages, so that small models have many

// The octahedron voxelized at 2^levels with random voxels strewn around it (so that the DAG does not reduce
// to a handful of pages), placed like a built .mvx, in encoding `e`.
MvxFile octahedron(Device& dev, uint32_t levels, Encoding e) {
  const uint32_t n = 1u << levels;
  Bounds b;
  b.extend(-1, -1, -1);
  b.extend(1, 1, 1);
  std::vector<uint64_t> voxels = ref::voxelize(octahedron_grid_triangles(n), n);
  std::mt19937_64 rng(levels);
  for (uint32_t i = 0; i < 40 * n; ++i) voxels.push_back(rng() & ((uint64_t{1} << (3 * levels)) - 1));
  std::sort(voxels.begin(), voxels.end());
  voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
  return mvx_for_dag(build_dag_for_format(dev, voxels, levels, e), e, grid_for_bounds(b, n), b);
}

// The file's DAG in pages (subtree order; an ssvdag in its own layout), read from memory; `fail` pages throw.
struct Paged {
  EncodedDag stream;  // its words
  PagedDag dag;
};
Paged paged(const MvxFile& f, std::vector<uint32_t> fail = {}) {
  Paged p;
  if (f.dag.encoding == Encoding::ssvdag) {
    PagedSsvdag s = paged_ssvdag(f.dag, kPageWords);
    p.stream.words = std::move(s.words);
    p.dag.level_starts = std::move(s.starts);
  } else {
    p.stream = paged_stream(f.dag, page_layout(f.dag, NodeOrder::subtree, kPageWords));
  }
  p.dag.grid = f.grid;
  p.dag.encoding = f.dag.encoding;
  p.dag.levels = f.dag.levels;
  p.dag.page_words = kPageWords;
  p.dag.pages = static_cast<uint32_t>((p.stream.words.size() + kPageWords - 1) / kPageWords);
  const std::vector<uint32_t>* words = &p.stream.words;
  p.dag.read = [words, fail](uint32_t page, std::span<uint32_t> out) {
    if (std::find(fail.begin(), fail.end(), page) != fail.end()) throw Error("injected read failure");
    for (uint32_t i = 0; i < out.size(); ++i) {
      const uint64_t w = uint64_t{page} * out.size() + i;
      out[i] = w < words->size() ? (*words)[w] : 0u;
    }
  };
  return p;
}

std::vector<uint32_t> download_words(Device& dev, const Buffer& b) {
  std::vector<uint32_t> v(b.bytes() / 4);
  dev.download(b, v.data(), b.bytes());
  return v;
}

// Every resident page's slot names it back, and every owned slot's page points at it.
void expect_table_consistent(Device& dev, PageCache& c) {
  const std::vector<uint32_t> table = download_words(dev, c.table()), owner = download_words(dev, c.owners());
  for (uint32_t pg = 0; pg < c.config().pages; ++pg) {
    if (table[pg] != MV_CACHE_NONE) {
      ASSERT_EQ(owner[table[pg]], pg) << "page " << pg;
    }
  }
  for (uint32_t s = 0; s < owner.size(); ++s) {
    if (owner[s] != MV_CACHE_NONE) {
      ASSERT_EQ(table[owner[s]], s) << "slot " << s;
    }
  }
}

// Camera-like rays from outside toward random points of the unit cube around the model.
std::vector<Ray> rays_at(uint32_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    for (int a = 0; a < 3; ++a) {
      r.origin[a] = 3.0f * u(rng);
      r.direction[a] = 0.8f * u(rng) - r.origin[a];
    }
  }
  return rays;
}

class PagedTraceTest : public ::testing::TestWithParam<DeviceInfo> {};

// Each pass of the kernel against the host build of the same code, started from the cache state the pass
// found (downloaded), until the cache holds everything the rays need.
// Preloaded: the cache is filled whole in page order before the first pass, which then needs nothing (one
// run of pages, no usage stamps). Streamed: the stamp-free kernel, which resolves a page outside the ray's run
// after its loop, walks each pass's state as the stamping kernel does. An ssvdag's kernels take its level starts
// from the table, then from the parameters, on every device.
void each_pass_matches_the_host(Device& dev, const MvxFile& f, bool preload, bool starts_in_params);

TEST_P(PagedTraceTest, EachPassMatchesTheHostBuildOfTheKernel) {
  Device& dev = shared_device(GetParam());
  for (Encoding e : {Encoding::svdag, Encoding::ssvdag})
    for (bool preload : {false, true})
      for (bool params : {false, true}) {
        if (params && e != Encoding::ssvdag) continue;
        SCOPED_TRACE(encoding_name(e) + (preload ? " preloaded" : " streamed") +
                     (params ? ", level starts from the parameters" : ""));
        each_pass_matches_the_host(dev, octahedron(dev, 6, e), preload, params);
      }
}

void each_pass_matches_the_host(Device& dev, const MvxFile& f, bool preload, bool starts_in_params) {
  Paged p = paged(f);
  ASSERT_GT(p.dag.pages, 8u);
  Tracer tracer(dev, p.dag, uint64_t{p.dag.pages} * kPageWords * 4, preload);
  if (f.dag.encoding == Encoding::ssvdag)
    tracer.engine().set_level_starts(starts_in_params ? TraceEngine::LevelStarts::parameters
                                                      : TraceEngine::LevelStarts::memory);
  if (preload) {
    EXPECT_EQ(tracer.preloaded().loaded, p.dag.pages);
    const std::vector<uint32_t> all = download_words(dev, tracer.cache()->table());
    for (uint32_t pg = 0; pg < p.dag.pages; ++pg) {  // slot = page, and one run of every page
      ASSERT_EQ(all[pg], pg);
      ASSERT_EQ(all[tracer.cache()->runs_at() + pg], mv_cache_run_word(0, p.dag.pages, pg));
    }
  }
  PageCache& cache = *tracer.cache();
  const uint32_t n = 2000;
  std::vector<uint32_t> rays(uint64_t{n} * MV_RAY_FLOATS);
  {
    const std::vector<Ray> world = rays_at(n, 5);
    const double side = f.grid.voxel_size * f.grid.resolution;
    for (uint32_t i = 0; i < n; ++i) {
      float c[6];
      for (int a = 0; a < 3; ++a) {
        c[a] = static_cast<float>((world[i].origin[a] - f.grid.origin[a]) / side);
        c[3 + a] = static_cast<float>(world[i].direction[a] / side);
      }
      mv_store_ray(rays.data(), i, MvRay{c[0], c[1], c[2], c[3], c[4], c[5], 1e30f, 0.0f});
    }
  }
  Buffer ray_buf = dev.alloc(rays.size() * 4, "rays");
  dev.upload(ray_buf, rays.data(), rays.size() * 4);
  Buffer hit_buf = dev.alloc(uint64_t{n} * MV_HIT_WORDS * 4, "hits");
  const uint32_t enc = f.dag.encoding == Encoding::ssvdag ? MV_ENC_PAGED_SSVDAG : MV_ENC_PAGED;
  uint32_t coarse_total = 0;
  for (uint32_t pass = 1; pass <= 64; ++pass) {
    SCOPED_TRACE("pass " + std::to_string(pass));
    tracer.begin_pass();
    std::vector<uint32_t> data = download_words(dev, cache.data()), table = download_words(dev, cache.table()),
                          usage = download_words(dev, cache.usage()), request = download_words(dev, cache.requests());
    std::vector<uint32_t> whole_hits;
    if (!preload) {  // the stamp-free kernel over the same state: its walks leave many short runs (mv_trace)
      tracer.engine().set_usage_stamps(false);
      tracer.engine().trace(&ray_buf, nullptr, 0, n, 0, 0.0f, 60000, false, hit_buf);
      tracer.engine().set_usage_stamps(true);
      whole_hits = download_words(dev, hit_buf);
    }
    tracer.engine().trace(&ray_buf, nullptr, 0, n, 0, 0.0f, 60000, false, hit_buf);
    const std::vector<uint32_t> hits = download_words(dev, hit_buf);
    if (!preload) EXPECT_EQ(whole_hits, hits) << "the two kernels walked differently";
    MvTraceParams tp{};
    tp.mode = MV_TRACE_MODE(f.dag.levels, 0u, 0u, 4u);  // pages of 16 words
    tp.max_steps = tracer.engine().step_limit(60000);
    for (uint32_t k = 0; starts_in_params && k < MV_TRACE_PAGED_PARAM_LEVELS && 3 + k <= f.dag.levels; ++k)
      tp.level_base[k] = static_cast<uint32_t>(p.dag.level_starts[3 + k]);
    tp.level_base[MV_TRACE_PAGE_STAMP] = cache.stamp();
    tp.level_base[MV_TRACE_PAGE_RUNS] = cache.runs_at();
    const uint32_t variant = (preload ? 0u : MV_TRACE_STAMPS) | (starts_in_params ? MV_TRACE_STARTS_IN_PARAMS : 0u);
    uint32_t coarse = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const MvHit want = mv_trace(data.data(), table.data(), nullptr, usage.data(), request.data(), enc, variant,
                                  mv_load_ray(reinterpret_cast<const float*>(rays.data()), i), 0.0f, tp);
      const MvHit got = mv_load_hit(hits.data(), i);
      ASSERT_EQ(got.info, want.info) << "ray " << i;
      ASSERT_EQ(MV_FBITS(got.t), MV_FBITS(want.t)) << "ray " << i;
      ASSERT_EQ(got.x, want.x);
      ASSERT_EQ(got.y, want.y);
      ASSERT_EQ(got.z, want.z);
      ASSERT_EQ(got.steps, want.steps);
      coarse += MV_INFO_COARSE(want.info);
    }
    EXPECT_EQ(download_words(dev, cache.usage()), usage);
    EXPECT_EQ(download_words(dev, cache.requests()), request);
    coarse_total += coarse;
    const CacheUpdateStats st = tracer.end_pass();
    expect_table_consistent(dev, cache);
    if (st.requested == 0) {
      EXPECT_EQ(coarse, 0u);
      if (preload) {
        EXPECT_EQ(pass, 1u);
        EXPECT_EQ(usage, download_words(dev, cache.usage()));  // no stamps: nothing to evict
        return;
      }
      EXPECT_GT(coarse_total, 0u);  // the early passes did stop at missing pages
      EXPECT_GT(pass, 2u);
      return;
    }
    ASSERT_FALSE(preload) << "a preloaded cache missed pages";
    EXPECT_GT(coarse, 0u);  // a request means some ray stopped at the missing page
  }
  FAIL() << "no convergence in 64 passes";
}

// Ray queries through a cache of an eighth of the pages equal the resident tracer's, for every 32-bit
// word encoding, once enough passes load what the batch needs (a narrow bundle: its working set fits).
TEST_P(PagedTraceTest, RayQueriesConvergeToTheResidentHits) {
  Device& dev = shared_device(GetParam());
  for (Encoding e : {Encoding::svo, Encoding::svdag, Encoding::ussvdag, Encoding::ssvdag}) {
    SCOPED_TRACE(encoding_name(e));
    const MvxFile f = octahedron(dev, 7, e);
    Paged p = paged(f);
    std::vector<Ray> rays(400);
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<float> u(-0.05f, 0.05f);
    for (Ray& r : rays) {  // from one eye toward a small patch of the surface
      r.origin[0] = 3, r.origin[1] = 0.2f, r.origin[2] = 0.1f;
      r.direction[0] = -3, r.direction[1] = -0.2f + u(rng), r.direction[2] = -0.1f + u(rng);
    }
    Tracer resident(dev, f);
    const std::vector<RayHit> want = resident.trace(rays);
    const uint64_t cache = std::max<uint64_t>(p.dag.pages / 8, 1) * kPageWords * 4;
    Tracer tracer(dev, p.dag, cache);
    ASSERT_LE(uint64_t{tracer.cache()->config().slots} * 8, p.dag.pages);
    const std::vector<RayHit> got = tracer.trace(rays);
    ASSERT_FALSE(tracer.last_passes().empty());
    EXPECT_EQ(tracer.last_passes().back().requested, 0u);
    expect_same_hits(got, want);
    expect_table_consistent(dev, *tracer.cache());
  }
}

// A picture through a cache 8 times smaller than the DAG (4 for an ssvdag; a close view: its working set
// fits), and a shaded one (shadow and AO rays reach further) through half of it: byte-identical to the
// resident renders.
TEST_P(PagedTraceTest, RenderConvergesToTheResidentPicture) {
  Device& dev = shared_device(GetParam());
  Camera cam;
  cam.eye[0] = 0.3, cam.eye[1] = 1.6, cam.eye[2] = 0.4;  // close to the top vertex
  cam.target[0] = 0, cam.target[1] = 0.9, cam.target[2] = 0;
  cam.fov = 10;
  for (Encoding e : {Encoding::svdag, Encoding::ssvdag})
  for (Shading shading : {Shading::normal, Shading::shaded}) {
    SCOPED_TRACE(encoding_name(e) + " " + shading_name(shading));
    const MvxFile f = octahedron(dev, 7, e);
    Paged p = paged(f);
    RenderOptions o;
    o.width = 96;
    o.height = 64;
    o.shading = shading;
    o.ao_samples = 2;
    o.read_ahead = true;  // on CPU devices too
    Tracer resident(dev, f);
    const RenderResult want = render(resident, cam, o);
    // an ssvdag's pages hold levels, not subtrees (paged_ssvdag.h): a ray's path meets more of them
    const uint32_t share = shading == Shading::shaded ? 2 : e == Encoding::ssvdag ? 4 : 8;
    const uint64_t cache = std::max<uint64_t>(p.dag.pages / share, 1) * kPageWords * 4;
    Tracer tracer(dev, p.dag, cache);
    const RenderResult got = render(tracer, cam, o);
    EXPECT_TRUE(got.converged);
    EXPECT_GT(got.cache.size(), 2u);
    EXPECT_EQ(got.coarse_pixels, 0u);
    EXPECT_EQ(got.hits, want.hits);
    EXPECT_TRUE(got.image.rgb == want.image.rgb) << "the converged picture differs from the resident one";
    EXPECT_GT(got.cache.front().requested, 0u);
    // shaded frames read the primary rays' missing pages ahead, while shadow and AO rays trace
    const CacheTotals t = cache_totals(got.cache);
    if (shading == Shading::shaded) EXPECT_GT(t.read_ahead, 0u);
    else EXPECT_EQ(t.read_ahead, 0u);
    EXPECT_LE(t.read_ahead, t.loaded);
  }
}

// A cache with a slot for every page is preloaded in page order: each frame (several views, plain and shaded)
// converges in its first pass, byte-identical to the resident render, with nothing loaded or evicted.
TEST_P(PagedTraceTest, PreloadedCacheRendersTheResidentPictureInOnePass) {
  Device& dev = shared_device(GetParam());
  for (Encoding e : {Encoding::svdag, Encoding::ssvdag}) {
    SCOPED_TRACE(encoding_name(e));
    const MvxFile f = octahedron(dev, 7, e);
    Paged p = paged(f);
    Tracer resident(dev, f);
    Tracer whole(dev, p.dag, uint64_t{p.dag.pages} * kPageWords * 4);
    EXPECT_EQ(whole.preloaded().loaded, p.dag.pages);
    EXPECT_EQ(whole.preloaded().evicted, 0u);
    for (const char* view : {"iso", "front", "top"})
    for (Shading shading : {Shading::normal, Shading::shaded}) {
      SCOPED_TRACE(std::string(view) + " " + shading_name(shading));
      RenderOptions o;
      o.width = 64;
      o.height = 48;
      o.shading = shading;
      o.ao_samples = 2;
      const Camera cam = view_camera(f.bounds, view);
      const RenderResult want = render(resident, cam, o);
      const RenderResult got = render(whole, cam, o);
      EXPECT_TRUE(got.converged);
      ASSERT_EQ(got.cache.size(), 1u);
      EXPECT_EQ(got.cache[0].requested, 0u);
      EXPECT_EQ(got.cache[0].loaded, 0u);
      EXPECT_EQ(got.coarse_pixels, 0u);
      EXPECT_TRUE(got.image.rgb == want.image.rgb) << "the preloaded picture differs from the resident one";
      // the beam pre-pass's grid, built through the cache, is the resident one: the rays start at the same places
      EXPECT_EQ(got.primary_steps, want.primary_steps);
      EXPECT_EQ(got.hit_steps, want.hit_steps);
    }
  }
}

// A whole view whose pages are twice the cache: no single pass can hold them, so the frame is rendered in
// bands of rows, each converging in turn, and the picture is still the resident one, byte for byte.
TEST_P(PagedTraceTest, ViewLargerThanTheCacheConvergesInBands) {
  Device& dev = shared_device(GetParam());
  const MvxFile f = octahedron(dev, 7, Encoding::svdag);
  Paged p = paged(f);
  const Camera cam = view_camera(f.bounds, "iso");
  RenderOptions o;
  o.width = 96;
  o.height = 64;
  o.shading = Shading::normal;
  o.lod_pixels = 0;
  Tracer resident(dev, f);
  const RenderResult want = render(resident, cam, o);
  Tracer whole(dev, p.dag, uint64_t{p.dag.pages} * kPageWords * 4, false);  // streamed: its passes tell the working set
  const RenderResult all = render(whole, cam, o);
  ASSERT_TRUE(all.converged);
  EXPECT_EQ(all.tiles, 1u);
  const uint32_t working_set = all.cache.back().used_slots;
  ASSERT_GT(working_set, 8u);
  Tracer tracer(dev, p.dag, uint64_t{working_set / 2} * kPageWords * 4);
  const RenderResult got = render(tracer, cam, o);
  EXPECT_TRUE(got.converged);
  EXPECT_GT(got.tiles, 1u);
  EXPECT_EQ(got.coarse_pixels, 0u);
  EXPECT_EQ(got.hits, want.hits);
  EXPECT_TRUE(got.image.rgb == want.image.rgb) << "the banded picture differs from the resident one";
  EXPECT_TRUE(std::any_of(got.cache.begin(), got.cache.end(), [](const CacheUpdateStats& st) { return st.over_capacity; }));
  expect_table_consistent(dev, *tracer.cache());
}

void one_page_cache_renders_the_roots_lod(Device& dev, const MvxFile& f);

// One slot: the root's page and nothing more. The picture is the coarse one (no error, every pixel shaded
// from resident data) and the render says it did not converge.
TEST_P(PagedTraceTest, OnePageCacheRendersTheRootsLevelOfDetail) {
  Device& dev = shared_device(GetParam());
  for (Encoding e : {Encoding::ussvdag, Encoding::ssvdag}) {
    SCOPED_TRACE(encoding_name(e));
    one_page_cache_renders_the_roots_lod(dev, octahedron(dev, 6, e));
  }
}

void one_page_cache_renders_the_roots_lod(Device& dev, const MvxFile& f) {
  Paged p = paged(f);
  Tracer tracer(dev, p.dag, kPageWords * 4);
  ASSERT_EQ(tracer.cache()->config().slots, 1u);
  RenderOptions o;
  o.width = 48;
  o.height = 32;
  o.shading = Shading::level;
  o.lod_pixels = 0;  // voxels: more than the root's page
  o.beam = false;     // (the beam's grid would load the root's page in a pass of its own, before the frame's)
  const RenderResult r = render(tracer, view_camera(f.bounds, "iso"), o);
  EXPECT_FALSE(r.converged);
  EXPECT_GT(r.hits, 0u);
  EXPECT_GT(r.coarse_pixels, 0u);
  ASSERT_GE(r.cache.size(), 2u);
  EXPECT_EQ(r.cache[0].loaded, 1u);  // the root's page
  EXPECT_TRUE(r.cache.back().over_capacity);
  EXPECT_EQ(r.image.rgb.size(), size_t{48} * 32 * 3);
  expect_table_consistent(dev, *tracer.cache());
  EXPECT_THROW(Tracer(dev, p.dag, kPageWords * 4 - 1), Error);
}

// Pages whose reads fail stay missing: the error is reported, the rest loads, and rendering goes on.
TEST_P(PagedTraceTest, FailingProducerLeavesPagesMissing) {
  Device& dev = shared_device(GetParam());
  for (Encoding e : {Encoding::svdag, Encoding::ssvdag})
  for (Shading shading : {Shading::normal, Shading::shaded}) {  // shaded: the read-ahead meets the failures first
    SCOPED_TRACE(encoding_name(e) + " " + shading_name(shading));
    const MvxFile f = octahedron(dev, 6, e);
    Paged good = paged(f);
    std::vector<uint32_t> fail;
    for (uint32_t pg = 1; pg < good.dag.pages; pg += 3) fail.push_back(pg);
    Paged p = paged(f, fail);
    Tracer tracer(dev, p.dag, uint64_t{p.dag.pages} * kPageWords * 4, false);  // streamed: the read-ahead sees failures
    RenderOptions o;
    o.width = 48;
    o.height = 32;
    o.shading = shading;
    o.ao_samples = 2;
    o.read_ahead = true;
    const RenderResult r = render(tracer, view_camera(f.bounds, "front"), o);
    EXPECT_FALSE(r.converged);
    uint32_t failed = 0, loaded = 0;
    std::string error;
    for (const CacheUpdateStats& st : r.cache) {
      failed += st.failed;
      loaded += st.loaded;
      if (error.empty()) error = st.first_error;
    }
    EXPECT_GT(failed, 0u);
    EXPECT_GT(loaded, 1u);
    EXPECT_NE(error.find("injected read failure"), std::string::npos) << error;
    EXPECT_GT(r.coarse_pixels, 0u);
    const std::vector<uint32_t> table = download_words(dev, tracer.cache()->table());
    for (uint32_t pg : fail) EXPECT_EQ(table[pg], MV_CACHE_NONE) << "page " << pg;
    expect_table_consistent(dev, *tracer.cache());
  }
}

// A device budget that leaves too little beside the page cache for the frame's per-pixel buffers: the frame is
// traced in bands of rows (each with its own first pixel, AO samples hashed by the frame's pixel), byte-identical
// to the frame traced whole, resident and paged; a budget without room for one row is a clear error.
TEST_P(PagedTraceTest, FrameBuffersOverTheBudgetAreTiled) {
  Device& dev = shared_device(GetParam());
  const MvxFile f = octahedron(dev, 6, Encoding::svdag);
  Paged p = paged(f);
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  o.shading = Shading::shaded;
  o.ao_samples = 2;
  const Camera cam = view_camera(f.bounds, "iso");
  Tracer whole(dev, f);
  const RenderResult want = render(whole, cam, o);
  ASSERT_EQ(want.tiles, 1u);
  auto small = Device::open({GetParam().selector(), 2u << 20, false});  // 2 MiB: 60 bytes a pixel is 4.6 MB
  for (bool paged_dag : {false, true}) {
    SCOPED_TRACE(paged_dag ? "paged" : "resident");
    Tracer tracer = paged_dag ? Tracer(*small, p.dag, uint64_t{p.dag.pages} * kPageWords * 4) : Tracer(*small, f);
    const RenderResult got = render(tracer, cam, o);
    EXPECT_GT(got.tiles, 2u);
    EXPECT_TRUE(got.converged);
    EXPECT_EQ(got.hits, want.hits);
    EXPECT_TRUE(got.image.rgb == want.image.rgb) << "the tiled frame differs from the whole one";
  }
  auto tiny = Device::open({GetParam().selector(), 512u << 10, false});
  Tracer tracer(*tiny, f);
  o.width = 8192;
  o.height = 2;
  const std::string msg = error_message([&] { render(tracer, cam, o); });
  EXPECT_NE(msg.find("one row of 8192 pixels needs"), std::string::npos) << msg;
}

TEST_P(PagedTraceTest, PagedSsvdagNeedsItsLevelStarts) {
  Device& dev = shared_device(GetParam());
  PagedDag d;
  d.encoding = Encoding::ssvdag;
  d.levels = 6;
  d.page_words = kPageWords;
  d.pages = 4;
  d.read = [](uint32_t, std::span<uint32_t>) {};
  EXPECT_NE(error_message([&] { Tracer(dev, d, 1 << 20); }).find("level starts"), std::string::npos);
  d.level_starts.assign(7, 0);
  d.level_starts[6] = 4 * kPageWords * 2;  // past the pages
  EXPECT_NE(error_message([&] { Tracer(dev, d, 1 << 20); }).find("past its pages"), std::string::npos);
  d.level_starts[6] = 4;
  d.level_starts[2] = 2;  // the walk finds the bricks at word 0
  EXPECT_NE(error_message([&] { Tracer(dev, d, 1 << 20); }).find("bricks start at word 0"), std::string::npos);
}

MV_INSTANTIATE_ON_ALL_DEVICES(PagedTraceTest);

}  // namespace
}  // namespace mv::test
