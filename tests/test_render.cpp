// Rendering: the device renderer against the CPU reference renderer (flat voxel DDA) for every shading mode,
// every encoding giving the same picture, and PNG output.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "reference.h"
#include "megavox/dag.h"
#include "megavox/encode.h"
#include "megavox/error.h"
#include "megavox/render.h"
#include "megavox/trace.h"
#include "voxel/build_steps.h"
#include "test_support.h"

namespace mv::test {
namespace {

// The octahedron voxelized at 64^3, placed like a built .mvx (grid in model units), in one encoding.
MvxFile octahedron_file(Device& dev, Encoding e) {
  const uint32_t levels = 6, n = 64;
  std::vector<uint64_t> voxels = ref::voxelize(octahedron_grid_triangles(n), n);
  Bounds b;
  b.extend(-1, -1, -1);
  b.extend(1, 1, 1);
  return mvx_for_dag(build_dag_for_format(dev, voxels, levels, e), e, grid_for_bounds(b, n), b);
}

size_t differing_pixels(const Image& a, const Image& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  size_t n = 0;
  for (size_t i = 0; i + 2 < std::min(a.rgb.size(), b.rgb.size()); i += 3)
    n += a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] || a.rgb[i + 2] != b.rgb[i + 2];
  return n;
}

class RenderTest : public ::testing::TestWithParam<DeviceInfo> {};

// Tolerance: at most 0.1 % of the pixels may differ (on CPU devices none do: the traversal is exact and the
// shading runs on the host).
TEST_P(RenderTest, EveryShadingModeMatchesTheReferenceRenderer) {
  Device& dev = shared_device(GetParam());
  MvxFile file = octahedron_file(dev, Encoding::ssvdag);
  Tracer tracer(dev, file);
  for (const char* view : {"iso", "front", "top"}) {
    for (Shading s : {Shading::shaded, Shading::normal, Shading::depth, Shading::level, Shading::heat}) {
      SCOPED_TRACE(std::string(view) + ", " + shading_name(s));
      RenderOptions o;
      o.width = 96;
      o.height = 64;
      o.shading = s;
      o.lod_pixels = s == Shading::level ? 4 : 1;
      Camera cam = view_camera(file.bounds, view);
      RenderResult got = render(tracer, cam, o);
      RenderResult want = render_reference(file, cam, o);
      EXPECT_EQ(got.hits, want.hits);
      EXPECT_GT(got.hits, o.width * o.height / 20);
      EXPECT_LE(differing_pixels(got.image, want.image), o.width * o.height / 1000);
    }
  }
}

TEST_P(RenderTest, AllEncodingsGiveTheSamePicture) {
  Device& dev = shared_device(GetParam());
  RenderOptions o;
  o.width = 80;
  o.height = 60;
  std::map<double, std::vector<uint8_t>> svo_image;  // by LOD
  for (Encoding e : {Encoding::svo, Encoding::svdag, Encoding::ussvdag, Encoding::ssvdag}) {
    MvxFile file = octahedron_file(dev, e);
    Tracer tracer(dev, file);
    for (double lod : {0.0, 3.0}) {
      o.lod_pixels = lod;
      std::vector<uint8_t> rgb = render(tracer, view_camera(file.bounds, "iso"), o).image.rgb;
      if (e == Encoding::svo) svo_image[lod] = rgb;
      EXPECT_TRUE(rgb == svo_image[lod]) << encoding_name(e) << ", lod " << lod;
    }
  }
}

TEST_P(RenderTest, BadCamerasAndOptionsAreErrors) {
  Bounds b;
  b.extend(0, 0, 0);
  b.extend(1, 2, 3);
  EXPECT_THROW(view_camera(b, "sideways"), Error);
  EXPECT_THROW(view_camera(Bounds{}, "iso"), Error);
  EXPECT_THROW(parse_shading("glossy"), Error);
  Device& dev = shared_device(GetParam());
  MvxFile file = octahedron_file(dev, Encoding::svdag);
  Tracer tracer(dev, file);
  Camera cam = view_camera(file.bounds, "front");
  RenderOptions o;
  o.width = 0;
  EXPECT_THROW(render(tracer, cam, o), Error);
  o.width = 16;
  o.height = 16;
  Camera same = cam;
  for (int a = 0; a < 3; ++a) same.target[a] = same.eye[a];
  EXPECT_THROW(render(tracer, same, o), Error);
  Camera parallel = cam;
  parallel.up[0] = 0, parallel.up[1] = 0, parallel.up[2] = 1;  // front looks along -z
  EXPECT_THROW(render(tracer, parallel, o), Error);
  o.ao_samples = 1000;
  EXPECT_THROW(render(tracer, cam, o), Error);
}

MV_INSTANTIATE_ON_ALL_DEVICES(RenderTest);

TEST(Render, DevicesGiveTheSameBytes) {
  if (all_devices().size() < 2) GTEST_SKIP() << "fewer than two devices to compare";
  RenderOptions o;
  o.width = 64;
  o.height = 48;
  std::vector<uint8_t> first;
  for (const DeviceInfo& d : all_devices()) {
    Device& dev = shared_device(d);
    MvxFile file = octahedron_file(dev, Encoding::ssvdag);
    Tracer tracer(dev, file);
    Image img = render(tracer, view_camera(file.bounds, "iso"), o).image;
    if (first.empty()) first = img.rgb;
    EXPECT_TRUE(img.rgb == first) << d.selector();
  }
}

TEST(Render, PngIsWrittenWholeOrNotAtAll) {
  Image img;
  img.width = 3;
  img.height = 2;
  img.rgb.assign(18, 200);
  const std::string path = ::testing::TempDir() + "megavox_test.png";
  write_png(path, img);
  std::ifstream in(path, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG");
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  std::remove(path.c_str());
  EXPECT_THROW(write_png("/nonexistent-dir/x.png", img), Error);
  img.rgb.pop_back();
  EXPECT_THROW(write_png(path, img), Error);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace mv::test
