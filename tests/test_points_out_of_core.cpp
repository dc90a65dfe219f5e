// The out-of-core sort (runs on disk, k-way merge, the builder on the merged prefix) gives the same file, byte
// for byte, as the in-core sort: synthetic LAS with every attribute and extra bytes, and the real clouds.
#include <gtest/gtest.h>

#include <fstream>

#include "megavox/point_build.h"
#include "point_fixture.h"
#include "test_support.h"

namespace mv::test {
namespace {

class PointsOutOfCoreTest : public ::testing::TestWithParam<DeviceInfo> {};

void expect_same_file(Device& dev, const std::string& input, uint64_t run_points, uint32_t max_node_points) {
  PointFileOptions o;
  o.input = input;
  o.build.max_node_points = max_node_points;
  o.build.prefix_points = 5000;
  o.output = temp_path("in_core.mvx");
  const PointFileReport a = build_points_file(dev, o);
  EXPECT_FALSE(a.out_of_core);
  o.output = temp_path("out_of_core.mvx");
  o.run_points = run_points;
  const PointFileReport b = build_points_file(dev, o);
  EXPECT_TRUE(b.out_of_core);
  EXPECT_GT(b.sort_runs, 1u);
  EXPECT_EQ(b.points_kept, a.points_kept);
  EXPECT_EQ(file_bytes(temp_path("in_core.mvx")), file_bytes(temp_path("out_of_core.mvx")));
}

TEST_P(PointsOutOfCoreTest, EqualsTheInCoreSort) {
  Device& dev = shared_device(GetParam());
  points::LasSpec spec;
  spec.minor = 4;
  spec.format = 8;
  spec.extra_bytes = 5;
  spec.wkt = "PROJCS[\"x\"]";
  std::vector<points::LasPoint> pts = points::las_points(20000, 5, 7);
  for (size_t i = 0; i < pts.size(); i += 3) pts[i].xyz[0] = pts[i / 2].xyz[0];  // repeated codes across runs
  const std::string las = temp_path("cloud.las");
  std::ofstream(las, std::ios::binary) << points::make_las(spec, pts);
  expect_same_file(dev, las, 1777, 200);
  for (const char* rel : {"pointcloud_lion_takanawa/lion_takanawa.ply", "pointcloud_autzen/autzen_trim.las"}) {
    const std::string path = shared_data_file(rel);
    if (path.empty()) {
      std::printf("PointsOutOfCoreTest: not run on %s: absent\n", rel);
      continue;
    }
    SCOPED_TRACE(rel);
    expect_same_file(dev, path, 40000, 4096);
  }
}

TEST_P(PointsOutOfCoreTest, BudgetTooSmallEvenOutOfCoreIsAClearError) {
  Device& dev = shared_device(GetParam());
  const std::string las = temp_path("small.las");
  std::ofstream(las, std::ios::binary) << points::make_las(points::LasSpec{}, points::las_points(5000, 0, 3));
  PointFileOptions o;
  o.input = las;
  o.output = temp_path("small.mvx");
  o.memory = 1000;
  const std::string msg = error_message([&] { build_points_file(dev, o); });
  EXPECT_NE(msg.find("even out of core"), std::string::npos) << msg;
  EXPECT_NE(msg.find("host memory budget"), std::string::npos) << msg;
  EXPECT_TRUE(file_bytes(o.output).empty());
}

MV_INSTANTIATE_ON_ALL_DEVICES(PointsOutOfCoreTest);

}  // namespace
}  // namespace mv::test
