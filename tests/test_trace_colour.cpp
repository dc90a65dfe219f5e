// Hit colours on every device: the kernel's walk to a hit's depth-first index (kernels/common/trace_colour.h)
// against a map from every node's cell to its pre-order index counted over the sorted voxels
// (host/ref/colour_reference.h), for every encoding (the ssvdag with mirrored clumps), voxels and coarser levels.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include "capi/capi_fixture.h"
#include "colour_reference.h"
#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/megavox.h"
#include "megavox/mvx.h"
#include "megavox/render.h"
#include "megavox/trace.h"
#include "point_fixture.h"
#include "test_support.h"

namespace mv::test {
namespace {

class TraceColourTest : public ::testing::TestWithParam<DeviceInfo> {};

// A sphere shell centred in a 64^3 grid, with a colour per point from its position: the geometry is symmetric, so
// the ssvdag stores mirrored subtrees, and the colours are not, so a wrong mirror picks a wrong colour.
std::string shell_cloud(const std::string& name) {
  std::vector<points::PlyColumn> cols = {{"float", "x", {}}, {"float", "y", {}}, {"float", "z", {}},
                                         {"uchar", "red", {}}, {"uchar", "green", {}}, {"uchar", "blue", {}}};
  const double pi = 3.14159265358979;
  for (int i = 0; i < 160; ++i)
    for (int j = 0; j < 320; ++j) {
      const double th = pi * (i + 0.5) / 160, ph = 2 * pi * j / 320;
      const double p[3] = {32 + 26 * std::sin(th) * std::cos(ph), 32 + 26 * std::sin(th) * std::sin(ph),
                           32 + 26 * std::cos(th)};
      for (int a = 0; a < 3; ++a) cols[a].values.push_back(p[a]);
      const uint32_t h = static_cast<uint32_t>(i * 7919 + j * 104729) * 2654435761u;
      for (int k = 0; k < 3; ++k) cols[3 + k].values.push_back(h >> (8 * k + 5) & 255);
    }
  cols[0].values.push_back(0), cols[1].values.push_back(0), cols[2].values.push_back(0);  // the cube: 0 .. 64
  cols[0].values.push_back(64), cols[1].values.push_back(64), cols[2].values.push_back(64);
  for (int k = 0; k < 3; ++k) cols[3 + k].values.insert(cols[3 + k].values.end(), {9.0, 250.0});
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << points::make_cloud_ply(ply::Fmt::le, cols);
  return path;
}

MvxFile coloured_file(Device& dev, const std::string& cloud, Encoding e) {
  const BuildOptions o = points::cloud_build_options(cloud, temp_path("shell_" + encoding_name(e) + ".mvx"), 64, e);
  build_mvx(dev, o);
  return read_mvx(o.output);
}

TEST_P(TraceColourTest, HitColoursAreTheDepthFirstEntriesOfTheHitCells) {
  Device& dev = shared_device(GetParam());
  const std::string cloud = shell_cloud("shell.ply");
  uint32_t seed = 11;
  auto next = [&] { return (seed = seed * 1664525u + 1013904223u) >> 8; };
  std::vector<Ray> rays;
  for (int i = 0; i < 3000; ++i) {
    Ray r;
    const float o[3] = {float(next() % 80) - 8, float(next() % 80) - 8, i % 3 == 0 ? -10.0f : 80.0f};
    const float to[3] = {20 + float(next() % 24), 20 + float(next() % 24), 20 + float(next() % 24)};
    for (int a = 0; a < 3; ++a) r.origin[a] = o[a], r.direction[a] = to[a] - o[a];
    if (i % 5 == 0) r.origin[0] = r.origin[1] = r.origin[2] = 32.25f;  // from inside the shell
    rays.push_back(r);
  }
  for (Encoding e : {Encoding::svdag, Encoding::ssvdag, Encoding::ussvdag, Encoding::svo}) {
    SCOPED_TRACE(encoding_name(e));
    const MvxFile f = coloured_file(dev, cloud, e);
    ASSERT_FALSE(f.colours.empty());
    const ref::NodeColours want(decode_encoded(f.dag), f.dag.levels, f.colours);
    Tracer tracer(dev, f);
    ASSERT_TRUE(tracer.has_colours());
    std::vector<uint32_t> got;
    const std::vector<RayHit> hits = tracer.trace(rays, {}, &got);
    ASSERT_EQ(got.size(), rays.size());
    size_t hit = 0, wrong = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const uint32_t expect = hits[i].hit ? want.at(0, hits[i].cell[0], hits[i].cell[1], hits[i].cell[2]) : 0;
      hit += hits[i].hit;
      wrong += got[i] != expect;
    }
    EXPECT_GT(hit, rays.size() / 2);
    EXPECT_EQ(wrong, 0u);

    // The same colours palette-compressed: the device holds and decodes the palette, with the same hit colours.
    MvxFile pal = f;
    pal.colour_storage = ColourStorage::palette;
    const std::string pal_path = temp_path("shell_palette_" + encoding_name(e) + ".mvx");
    write_mvx(pal_path, pal);
    const MvxFile g = read_mvx(pal_path);
    ASSERT_TRUE(g.colour_palette);
    Tracer palette_tracer(dev, g);
    std::vector<uint32_t> from_palette;
    palette_tracer.trace(rays, {}, &from_palette);
    EXPECT_TRUE(from_palette == got);

    // Coarser levels of detail: the flat colour picture equals the reference's, whose colours come from the map.
    for (double lod : {1.0, 6.0}) {
      RenderOptions ro;
      ro.width = 80;
      ro.height = 60;
      ro.shading = Shading::colour;
      ro.lod_pixels = lod;
      const Camera cam = view_camera(f.bounds, lod > 1 ? "iso" : "front");
      const RenderResult r = render(tracer, cam, ro), w = render_reference(f, cam, ro);
      EXPECT_GT(r.hits, ro.width * ro.height / 10);
      size_t differ = 0;
      for (size_t k = 0; k < r.image.rgb.size() && k < w.image.rgb.size(); ++k) differ += r.image.rgb[k] != w.image.rgb[k];
      EXPECT_EQ(r.image.rgb.size(), w.image.rgb.size());
      EXPECT_EQ(differ, 0u) << "lod " << lod;
    }
  }
}

TEST_P(TraceColourTest, ColourlessFilesAndOffLeaveHitsGrey) {
  Device& dev = shared_device(GetParam());
  const std::string cloud = shell_cloud("shell_grey.ply");
  const MvxFile f = coloured_file(dev, cloud, Encoding::svdag);
  Tracer off(dev, f, false);
  EXPECT_FALSE(off.has_colours());
  std::vector<uint32_t> got{1, 2, 3};
  Ray r;
  r.origin[0] = r.origin[1] = 32, r.origin[2] = -5;
  off.trace({r}, {}, &got);
  EXPECT_TRUE(got.empty());
  RenderOptions ro;
  ro.width = 32;
  ro.height = 24;
  ro.ao_samples = 0;
  Tracer on(dev, f);
  const Camera cam = view_camera(f.bounds, "front");
  const Image a = render(on, cam, ro).image, b = render(off, cam, ro).image;
  EXPECT_TRUE(a.rgb != b.rgb);
  ro.colours = false;
  EXPECT_TRUE(render(on, cam, ro).image.rgb == b.rgb);
  MvxFile wrong = f;
  wrong.colours.resize(wrong.colours.size() - 3);
  EXPECT_THROW(Tracer(dev, wrong), Error);
}

// Streamed through a page cache that loads what the rays ask for, every encoding and page order, raw and palette
// colours: the same hits and the same colours as the resident tracer; through the C API too, with a cache of a
// third of the file's pages (evicting as it goes; a version 5 file's size plane).
TEST_P(TraceColourTest, StreamedScenesFindTheirColoursThroughTheCache) {
  Device& dev = shared_device(GetParam());
  const std::string cloud = shell_cloud("shell_paged.ply"), path = temp_path("shell_paged.mvx");
  std::vector<Ray> rays;
  for (int i = 0; i < 1500; ++i) {
    Ray r;
    const float a = 0.0042f * float(i), o[3] = {32 + 60 * std::cos(a), 32 + 60 * std::sin(a), 20 + float(i % 25)};
    for (int k = 0; k < 3; ++k) r.origin[k] = o[k], r.direction[k] = 32 + float((i * 7 + 3 * k) % 19) - 9 - o[k];
    rays.push_back(r);
  }
  for (Encoding e : {Encoding::svdag, Encoding::ssvdag, Encoding::ussvdag, Encoding::svo}) {
    const MvxFile f = coloured_file(dev, cloud, e);
    Tracer resident(dev, f);
    std::vector<uint32_t> want;
    const std::vector<RayHit> hits = resident.trace(rays, {}, &want);
    const ref::NodeColours reference(decode_encoded(f.dag), f.dag.levels, f.colours);
    for (size_t i = 0; i < rays.size(); ++i)  // the resident walk's colours, as the reference has them
      ASSERT_EQ(want[i], hits[i].hit ? reference.at(hits[i].level, hits[i].cell[0], hits[i].cell[1], hits[i].cell[2]) : 0);
    for (NodeOrder order : {NodeOrder::subtree, NodeOrder::level})
      for (ColourStorage storage : {ColourStorage::raw, ColourStorage::palette}) {
        if (e == Encoding::ssvdag && order == NodeOrder::subtree) continue;  // always level order
        SCOPED_TRACE(encoding_name(e) + (order == NodeOrder::level ? " level " : " subtree ") +
                     (storage == ColourStorage::raw ? "raw" : "palette"));
        MvxFile g = f;
        g.colour_storage = storage;
        write_mvx(path, g, {64, order});
        PagedDag d = open_paged_mvx(path);
        ASSERT_EQ(d.plane_words, 64u * (e == Encoding::ssvdag ? 2u : 1u));
        const uint64_t slot = (64 + d.plane_words) * 4;  // a page and its size plane
        const uint64_t all = d.pages * slot;
        Tracer paged(dev, std::move(d), all, false);  // loaded as the rays ask, not preloaded
        ASSERT_TRUE(paged.has_colours());
        std::vector<uint32_t> got;
        EXPECT_GT(expect_same_hits(paged.trace(rays, {}, &got), hits), rays.size() / 3);
        EXPECT_GT(paged.last_passes().size(), 1u);
        EXPECT_TRUE(got == want);
        if (storage == ColourStorage::palette) continue;
        // a picture through a cache of half the pages: the resident one, its colours included
        RenderOptions ro;
        ro.width = 96;
        ro.height = 72;
        ro.shading = Shading::colour;
        const Camera cam = view_camera(f.bounds, "iso");
        PagedDag h = open_paged_mvx(path);
        const uint64_t half = std::max<uint64_t>(h.pages / 2, 24) * slot;  // (a small DAG's view needs 24)
        Tracer streamed(dev, std::move(h), half);
        const RenderResult r = render(streamed, cam, ro), w = render(resident, cam, ro);
        EXPECT_GT(w.hits, ro.width * ro.height / 10);
        EXPECT_TRUE(r.converged);
        size_t differ = 0;
        for (size_t k = 0; k < r.image.rgb.size() && k < w.image.rgb.size(); ++k) differ += r.image.rgb[k] != w.image.rgb[k];
        EXPECT_EQ(differ, 0u);
        EXPECT_TRUE(r.image.rgb == w.image.rgb);
      }
  }
  // the C API: a coloured octree streamed through a cache of a third of its pages answers the resident bytes
  const MvxFile f = coloured_file(dev, cloud, Encoding::svo);
  write_mvx(path, f, {16, NodeOrder::level});
  const PagedDag d = open_paged_mvx(path);
  ASSERT_GT(d.pages, 3u * 64);  // a cache needs 64 pages at least (16 words each, and as many plane words)
  capi::CDevice flat(GetParam()), small(GetParam(), "cache_memory=" + std::to_string(d.pages / 3 * 128));
  ASSERT_TRUE(flat.handle && small.handle);
  MvScene a = mvOpenScene(flat.handle, path.c_str()), b = mvOpenScene(small.handle, path.c_str());
  ASSERT_TRUE(a && b) << mvGetDeviceLastErrorMessage(small.handle);
  MvSceneInfo info;
  ASSERT_EQ(mvGetSceneInfo(a, &info), MV_ERROR_NONE);
  const std::vector<MvTraceRay> crays = capi::random_rays(info, 2000, 9);
  std::vector<MvTraceHit> ha(crays.size()), hb(crays.size());
  std::vector<uint8_t> ca(4 * crays.size()), cb(4 * crays.size(), 7);
  ASSERT_EQ(mvTraceRaysRgba(a, crays.data(), ha.data(), ca.data(), crays.size(), nullptr), MV_ERROR_NONE);
  ASSERT_EQ(mvTraceRaysRgba(b, crays.data(), hb.data(), cb.data(), crays.size(), nullptr), MV_ERROR_NONE)
      << mvGetDeviceLastErrorMessage(small.handle);
  EXPECT_EQ(std::memcmp(ha.data(), hb.data(), ha.size() * sizeof(MvTraceHit)), 0);
  EXPECT_TRUE(ca == cb);
  EXPECT_GT(std::count_if(cb.begin(), cb.end(), [](uint8_t v) { return v != 0; }), 1000);
  MvSceneStats st{};
  st.byteSize = sizeof st;
  ASSERT_EQ(mvGetSceneStats(b, &st), MV_ERROR_NONE);
  EXPECT_EQ(st.paged, 1u);
  EXPECT_GT(st.pagesStreamed, 0u);
  uint64_t entries = 0;
  ASSERT_EQ(mvGetSceneColourEntries(b, &entries), MV_ERROR_NONE);
  EXPECT_EQ(entries, f.colours.size() / 3);
  mvReleaseScene(a);
  mvReleaseScene(b);
}

// The C API's optional colour output equals the C++ tracer's; a scene without colours gives zeros.
TEST_P(TraceColourTest, TheCApiReturnsTheSameColoursBesideTheHits) {
  capi::CDevice dev(GetParam());
  ASSERT_TRUE(dev.handle);
  const std::string cloud = shell_cloud("shell_capi.ply"), path = temp_path("shell_capi.mvx");
  MvBuildArguments a;
  mvInitBuildArguments(&a);
  a.resolution = 64;
  a.format = "ssvdag";
  a.gridOrigin = "min";
  a.output = path.c_str();
  MvScene scene = mvBuildSceneFromFile(dev.handle, cloud.c_str(), &a);
  ASSERT_TRUE(scene) << mvGetDeviceLastErrorMessage(dev.handle);
  MvSceneInfo info;
  ASSERT_EQ(mvGetSceneInfo(scene, &info), MV_ERROR_NONE);
  const std::vector<MvTraceRay> rays = capi::random_rays(info, 2000, 5);
  std::vector<MvTraceHit> hits(rays.size());
  std::vector<uint8_t> rgba(4 * rays.size(), 7);
  ASSERT_EQ(mvTraceRaysRgba(scene, rays.data(), hits.data(), rgba.data(), rays.size(), nullptr), MV_ERROR_NONE)
      << mvGetDeviceLastErrorMessage(dev.handle);
  const MvxFile f = read_mvx(path);
  uint64_t entries = 0;
  ASSERT_EQ(mvGetSceneColourEntries(scene, &entries), MV_ERROR_NONE);
  EXPECT_EQ(entries, f.colours.size() / 3);
  Tracer tracer(shared_device(GetParam()), f);
  std::vector<Ray> cpp(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    for (int k = 0; k < 3; ++k) cpp[i].origin[k] = rays[i].org[k], cpp[i].direction[k] = rays[i].dir[k];
    cpp[i].tmax = rays[i].tmax;
  }
  std::vector<uint32_t> want;
  tracer.trace(cpp, {}, &want);
  size_t wrong = 0, coloured = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    uint32_t got = 0;
    for (int k = 0; k < 4; ++k) got |= uint32_t{rgba[4 * i + k]} << (8 * k);
    wrong += got != want[i];
    coloured += got != 0;
    EXPECT_EQ(got != 0, std::isfinite(hits[i].t));
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(coloured, rays.size() / 10);
  mvReleaseScene(scene);

  const capi::Mesh m = capi::octahedron();  // a mesh: no colours, so zeros
  a.format = "svdag";
  a.output = nullptr;
  a.gridOrigin = "center";
  MvScene grey = mvBuildSceneFromMemory(dev.handle, m.positions.data(), 6, m.indices.data(), 8, &a);
  ASSERT_TRUE(grey) << mvGetDeviceLastErrorMessage(dev.handle);
  ASSERT_EQ(mvGetSceneColourEntries(grey, &entries), MV_ERROR_NONE);
  EXPECT_EQ(entries, 0u);
  ASSERT_EQ(mvGetSceneInfo(grey, &info), MV_ERROR_NONE);
  const std::vector<MvTraceRay> few = capi::random_rays(info, 200, 3);
  hits.resize(few.size());
  rgba.assign(4 * few.size(), 7);
  ASSERT_EQ(mvTraceRaysRgba(grey, few.data(), hits.data(), rgba.data(), few.size(), nullptr), MV_ERROR_NONE);
  EXPECT_EQ(std::count(rgba.begin(), rgba.end(), 0), static_cast<std::ptrdiff_t>(rgba.size()));
  mvReleaseScene(grey);
}

MV_INSTANTIATE_ON_ALL_DEVICES(TraceColourTest);

}  // namespace
}  // namespace mv::test
