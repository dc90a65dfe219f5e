// `megavox points build` on the real clouds of the shared data (Autzen LAS and PLY, the lion, the Kinect scans):
// the oracles hold, the device build equals the top-down reference byte for byte on every backend, the file
// reads back, and the render covers the picture.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/point_source.h"
#include "megavox/mvx.h"
#include "megavox/point_build.h"
#include "megavox/point_render.h"
#include "points_oracles.h"
#include "points_reference.h"
#include "test_support.h"

namespace mv::test {
namespace {

class PointsRealTest : public ::testing::TestWithParam<DeviceInfo> {};

PointColumns read_all(const std::string& path, PointCloudInfo& info) {
  auto src = io::open_points(path);
  info = src->info();
  PointColumns c;
  while (src->next(c, 1 << 16)) {
  }
  return c;
}

TEST_P(PointsRealTest, SharedCloudsBuildExactlyAndRender) {
  Device& dev = shared_device(GetParam());
  bool any = false;
  for (const char* rel : {"pointcloud_autzen/autzen_trim.las", "pointcloud_autzen/autzen_trim.ply",
                          "pointcloud_lion_takanawa/lion_takanawa.ply", "rgbd_kinect/milk_cartoon_clorox.ply",
                          "rgbd_kinect/region_growing_rgb.ply"}) {
    const std::string path = shared_data_file(rel);
    if (path.empty()) continue;
    any = true;
    SCOPED_TRACE(rel);
    PointCloudInfo info;
    const PointColumns cloud = read_all(path, info);
    // The file pipeline: read, sort, build, write; then the file read back.
    PointFileOptions o;
    o.input = path;
    o.output = temp_path("real.mvx");
    o.build.max_node_points = 4096;
    PointFileReport r = build_points_file(dev, o);
    EXPECT_EQ(r.points_in, cloud.size());
    EXPECT_EQ(r.points_kept, cloud.size());
    PointHierarchy h = read_mvx_points(o.output);
    expect_valid(h, cloud);
    // The top-down reference with the same rule.
    ref::PointLodRule rule{point_depth_for(cloud.size(), 4096), 4096, 6};
    expect_same(h, ref::build_point_hierarchy(cloud, info, rule));
    PointRenderOptions ro;
    ro.width = 320;
    ro.height = 200;
    PointRenderResult pic = render_points(dev, h, ro);
    EXPECT_GT(pic.pixels_covered, 320u * 200u / 50) << "the picture is nearly empty";
    std::filesystem::remove(o.output);
  }
  if (!any) std::printf("PointsRealTest: not run: no point clouds in %s\n", shared_data_path("").c_str());
}

MV_INSTANTIATE_ON_ALL_DEVICES(PointsRealTest);

}  // namespace
}  // namespace mv::test
