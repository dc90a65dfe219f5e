// The splat kernels against their plain C++ reference on every backend, views and options, and bad options.
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "megavox/point_render.h"
#include "points/point_frame.h"
#include "points_reference.h"
#include "splat_reference.h"
#include "test_support.h"

namespace mv::test {
namespace {

class PointsRenderTest : public ::testing::TestWithParam<DeviceInfo> {};

PointHierarchy sample(bool z_up, uint64_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  PointColumns c;
  PointCloudInfo info;
  info.z_up = z_up;
  info.scale[2] = 0.25;  // anisotropic, as LAS files often are
  std::normal_distribution<double> g(0, 1);
  for (uint64_t i = 0; i < n; ++i) {
    double x = g(rng), y = g(rng), z = g(rng);
    const double len = std::sqrt(x * x + y * y + z * z) + 1e-9;  // a sphere's surface, plus a few strays
    const double r = i % 97 == 0 ? 3.0 : 1.0;
    c.xyz.insert(c.xyz.end(), {static_cast<int32_t>(x / len * r * 40000), static_cast<int32_t>(y / len * r * 40000),
                               static_cast<int32_t>(z / len * r * 160000)});
  }
  info.points = n;
  return ref::build_point_hierarchy(c, info, ref::PointLodRule{8, 500, 6});
}

TEST_P(PointsRenderTest, KernelsMatchTheReference) {
  Device& dev = shared_device(GetParam());
  const PointHierarchy h = sample(true, 30000, 4);
  for (const char* view : {"iso", "front", "top", "left"})
    for (uint32_t size : {1u, 3u, 6u}) {
      SCOPED_TRACE(std::string(view) + " size " + std::to_string(size));
      PointRenderOptions o;
      o.width = 300;
      o.height = 180;
      o.view = view;
      o.point_size = size;
      o.lod_pixels = size == 6 ? 4 : 1;
      PointRenderResult r = render_points(dev, h, o);
      const ::mv::points::SplatFrame f = ::mv::points::splat_frame(h, o);
      std::vector<uint32_t> depth, index;
      ref::splat_reference(f, depth, index);
      ASSERT_EQ(r.depth, depth);
      ASSERT_EQ(r.winner, index);
      EXPECT_EQ(r.image.rgb, ::mv::points::resolve_frame(f, depth, index).rgb);
      EXPECT_GT(r.pixels_covered, 300u * 180u / 50);
    }
}

TEST_P(PointsRenderTest, CoarserCutsDrawFewerPoints) {
  Device& dev = shared_device(GetParam());
  const PointHierarchy h = sample(false, 40000, 8);
  PointRenderOptions fine, coarse;
  fine.width = coarse.width = 200;
  fine.height = coarse.height = 150;
  coarse.lod_pixels = 16;
  const PointRenderResult a = render_points(dev, h, fine), b = render_points(dev, h, coarse);
  EXPECT_LT(b.points_drawn, a.points_drawn);
  EXPECT_LT(b.nodes_drawn, a.nodes_drawn);
}

TEST(PointsRender, BadOptionsAreClearErrors) {
  const PointHierarchy h = sample(true, 100, 1);
  PointRenderOptions o;
  o.view = "sideways";
  EXPECT_NE(error_message([&] { ::mv::points::splat_frame(h, o); }).find("unknown view"), std::string::npos);
  o = {};
  o.width = 0;
  EXPECT_NE(error_message([&] { ::mv::points::splat_frame(h, o); }).find("pixels"), std::string::npos);
  o = {};
  o.up = std::array<double, 3>{0, 0, 0};
  EXPECT_NE(error_message([&] { ::mv::points::splat_frame(h, o); }).find("the up direction"), std::string::npos);
  o = {};
  o.fov = 0;
  EXPECT_NE(error_message([&] { ::mv::points::splat_frame(h, o); }).find("the field of view"), std::string::npos);
  try {
    ::mv::points::splat_frame(h, o);
  } catch (const Error& e) {
    EXPECT_EQ(e.settings, setting_fov);  // the CLI names it --fov
  }
}

// --up as a vector: the file's own axis gives the default camera bit for bit; a tilted one, another camera. An eye
// and target in the cloud's units place the camera there: far out along the view of `front`, the same view.
TEST(PointsRender, UpVectorsAndEyes) {
  const PointHierarchy h = sample(true, 3000, 2);
  auto params = [&](const PointRenderOptions& o) {
    const MvSplatParams p = ::mv::points::splat_frame(h, o).params;
    return std::vector<uint8_t>(reinterpret_cast<const uint8_t*>(&p), reinterpret_cast<const uint8_t*>(&p + 1));
  };
  PointRenderOptions o;
  o.width = 200;
  o.height = 150;
  PointRenderOptions axis = o, tilted = o;
  axis.up = std::array<double, 3>{0, 0, 2};
  tilted.up = std::array<double, 3>{0, 0.3, 1};
  EXPECT_EQ(params(o), params(axis));
  EXPECT_NE(params(o), params(tilted));
  // The cloud's centre in its own units (world = offset + scale * xyz); front with +Z up looks along +Y.
  const ::mv::points::FrameBox box = ::mv::points::points_box(h.points);
  std::array<double, 3> centre{};
  for (int a = 0; a < 3; ++a) centre[a] = h.source.offset[a] + h.source.scale[a] * 0.5 * double(box.lo[a] + box.hi[a]);
  PointRenderOptions front = o, eye = o;
  front.view = "front";
  eye.eye = centre;
  (*eye.eye)[1] -= 1e6;
  eye.target = centre;
  const ::mv::points::SplatFrame f = ::mv::points::splat_frame(h, front), e = ::mv::points::splat_frame(h, eye);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(f.params.rot[i], e.params.rot[i], 2) << i;
  EXPECT_LT(e.params.eye_y, f.params.eye_y);
  eye.up = std::array<double, 3>{0, 1, 0};  // along the view
  EXPECT_NE(error_message([&] { ::mv::points::splat_frame(h, eye); }).find("the up direction"), std::string::npos);
}

MV_INSTANTIATE_ON_ALL_DEVICES(PointsRenderTest);

}  // namespace
}  // namespace mv::test
