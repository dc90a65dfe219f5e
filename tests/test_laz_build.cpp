// Every attribute through a point build: a LAZ cloud (LAS 1.2 format 3 and LAS 1.4 format 8 with typed extra
// bytes) built into a .mvx point hierarchy keeps, at its leaves, exactly the input's points with every field
// of each (position, intensity, colour and the whole attribute record), on every device, and the file names the
// fields as the reader did.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include "io/point_source.h"
#include "megavox/mvx.h"
#include "megavox/point_build.h"
#include "test_support.h"

namespace mv::test {
namespace {

class LazBuildTest : public ::testing::TestWithParam<DeviceInfo> {};

// One point with everything it carries, comparable.
using Row = std::tuple<std::vector<int32_t>, uint16_t, std::vector<uint16_t>, std::vector<uint8_t>>;

std::vector<Row> rows(const PointColumns& c, uint32_t extra_bytes, uint64_t first, uint64_t count) {
  std::vector<Row> out;
  for (uint64_t i = first; i < first + count; ++i) {
    Row r;
    std::get<0>(r).assign(c.xyz.begin() + 3 * i, c.xyz.begin() + 3 * i + 3);
    std::get<1>(r) = c.intensity.empty() ? 0 : c.intensity[i];
    if (!c.rgb.empty()) std::get<2>(r).assign(c.rgb.begin() + 3 * i, c.rgb.begin() + 3 * i + 3);
    std::get<3>(r).assign(c.extra.begin() + extra_bytes * i, c.extra.begin() + extra_bytes * (i + 1));
    out.push_back(std::move(r));
  }
  return out;
}

TEST_P(LazBuildTest, LeavesKeepEveryPointWithEveryField) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_laz/autzen_trim.laz");
  Device& dev = shared_device(GetParam());
  for (const char* name : {"pointcloud_laz/autzen_trim.laz", "pointcloud_laz/las_with_several_extra_byte_bloc.laz"}) {
    const std::string in = shared_data_file(name), out = temp_path("laz_build.mvx");
    auto src = io::open_points(in);
    const PointCloudInfo info = src->info();
    PointColumns all;
    while (src->next(all, 1 << 16)) {
    }
    PointFileOptions o;
    o.input = in;
    o.output = out;
    o.build.max_node_points = 20000;
    build_points_file(dev, o);
    const PointHierarchy h = read_mvx_points(out);
    EXPECT_EQ(h.source.fields, info.fields) << name;
    EXPECT_EQ(h.source.extra_bytes, info.extra_bytes) << name;
    ASSERT_EQ(h.points_kept, info.points) << name;

    std::vector<Row> leaves;
    for (const PointNode& n : h.nodes) {
      if (!n.leaf()) continue;
      std::vector<Row> r = rows(h.points, h.source.extra_bytes, n.first_point, n.point_count);
      leaves.insert(leaves.end(), r.begin(), r.end());
    }
    std::vector<Row> want = rows(all, info.extra_bytes, 0, all.size());
    std::sort(leaves.begin(), leaves.end());
    std::sort(want.begin(), want.end());
    EXPECT_TRUE(leaves == want) << name << ": the leaves do not hold the input's points with their fields";
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(LazBuildTest);

}  // namespace
}  // namespace mv::test
