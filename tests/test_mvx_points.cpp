// The point content of .mvx (version 2): round trips of every column, version-1 voxel files still open, the
// kinds refuse each other, and damage (bytes, structure with valid checksums, truncation) is a clear error.
#include <gtest/gtest.h>
#include <xxhash.h>

#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "io/mvx_format.h"
#include "megavox/dag.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "points_reference.h"
#include "test_support.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;

PointHierarchy sample_points(bool attributes) {
  std::mt19937_64 rng(3);
  PointColumns c;
  PointCloudInfo info;
  info.format = "test cloud";
  info.crs = attributes ? "PROJCS[\"test\"]" : "";
  info.z_up = attributes;
  info.scale[0] = 0.01;
  info.offset[2] = 100;
  for (int i = 0; i < 3000; ++i) {
    c.xyz.insert(c.xyz.end(), {static_cast<int32_t>(rng() % 5000), static_cast<int32_t>(rng() % 700),
                               -static_cast<int32_t>(rng() % 90000)});
    if (attributes) {
      c.rgb.insert(c.rgb.end(), {static_cast<uint16_t>(rng()), 1, 2});
      c.normal.insert(c.normal.end(), {0.f, 1.f, static_cast<float>(i)});
      c.intensity.push_back(static_cast<uint16_t>(i));
      for (int k = 0; k < 3; ++k) c.extra.push_back(static_cast<uint8_t>(i + k));
    }
  }
  if (attributes) {
    info.attributes = kPointRgb | kPointNormal | kPointIntensity | kPointExtra;
    info.extra_bytes = 3;
  }
  info.points = c.size();
  return ref::build_point_hierarchy(c, info, ref::PointLodRule{7, 100, 6});
}

TEST(MvxPoints, RoundTripsEveryColumn) {
  for (bool attributes : {false, true}) {
    PointHierarchy h = sample_points(attributes);
    const std::string p = temp_path("points.mvx");
    write_mvx_points(p, h);
    EXPECT_FALSE(fs::exists(p + ".tmp"));
    EXPECT_EQ(mvx_content(p), MvxContent::points);
    PointHierarchy g = read_mvx_points(p);
    ASSERT_EQ(g.nodes.size(), h.nodes.size());
    EXPECT_EQ(0, std::memcmp(g.nodes.data(), h.nodes.data(), h.nodes.size() * sizeof(PointNode)));
    EXPECT_EQ(g.points.xyz, h.points.xyz);
    EXPECT_EQ(g.points.rgb, h.points.rgb);
    EXPECT_EQ(g.points.normal, h.points.normal);
    EXPECT_EQ(g.points.intensity, h.points.intensity);
    EXPECT_EQ(g.points.extra, h.points.extra);
    EXPECT_EQ(g.nodes_per_level, h.nodes_per_level);
    EXPECT_EQ(g.source.crs, h.source.crs);
    EXPECT_EQ(g.source.format, "test cloud");
    EXPECT_EQ(g.source.z_up, attributes);
    EXPECT_EQ(g.source.scale[0], 0.01);
    EXPECT_EQ(g.source.offset[2], 100);
    EXPECT_EQ(g.points_kept, 3000u);
    EXPECT_EQ(g.shift, h.shift);
    // The bytes of a file depend on its content alone.
    const std::vector<char> once = file_bytes(p);
    write_mvx_points(p, g);
    EXPECT_EQ(file_bytes(p), once);
    EXPECT_NE(error_message([&] { read_mvx(p); }).find("point cloud"), std::string::npos);
  }
}

class MvxVersionTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(MvxVersionTest, VersionOneVoxelFilesStillOpen) {
  // A version 1 header is a version 2 (or unpaged version 3) header with 0 in the content field: patch an
  // unpaged voxel file back to 1.
  std::vector<uint64_t> voxels{0, 9, 63, 64 * 64 * 64 - 1};
  Dag dag = build_svdag(shared_device(GetParam()), voxels, 6);
  MvxFile f;
  f.grid.resolution = 64;
  f.voxels = dag.voxels;
  f.svo_nodes = dag.svo_nodes;
  f.dag_nodes.push_back(dag.voxels);
  for (uint32_t l = 1; l <= dag.levels; ++l) f.dag_nodes.push_back(dag.nodes(l));
  f.dag = encode_svdag(dag);
  const std::string p = temp_path("v1.mvx");
  try {
    write_mvx(p, f, {0, NodeOrder::level});
  } catch (const Error& e) {
    GTEST_FAIL() << "the sample voxel file is not valid: " << e.what();
  }
  std::vector<char> b = file_bytes(p);
  mvx_format::Header h;
  std::memcpy(&h, b.data(), sizeof h);
  EXPECT_EQ(h.version, kMvxVersion);
  h.version = 1;
  h.checksum = XXH3_64bits(&h, offsetof(mvx_format::Header, checksum));
  std::memcpy(b.data(), &h, sizeof h);
  write_bytes(p, b);
  EXPECT_EQ(read_mvx(p).voxels, 4u);
  EXPECT_EQ(mvx_content(p), MvxContent::voxels);
  EXPECT_NE(error_message([&] { read_mvx_points(p); }).find("holds voxels"), std::string::npos);
  // A version-1 header that claims point content is damage.
  h.content = mvx_format::kPoints;
  h.checksum = XXH3_64bits(&h, offsetof(mvx_format::Header, checksum));
  std::memcpy(b.data(), &h, sizeof h);
  write_bytes(p, b);
  EXPECT_NE(error_message([&] { read_mvx(p); }).find("version 1"), std::string::npos);
}

TEST(MvxPoints, DamageIsAClearError) {
  PointHierarchy h = sample_points(true);
  const std::string p = temp_path("damage_points.mvx");
  write_mvx_points(p, h);
  const std::vector<char> good = file_bytes(p);
  const std::string q = temp_path("damaged_points.mvx");
  // Flips anywhere, truncations anywhere: each read fails with mv::Error or returns a valid hierarchy (padding).
  std::mt19937_64 rng(5);
  for (int i = 0; i < 600; ++i) {
    std::vector<char> b = good;
    b[rng() % b.size()] ^= static_cast<char>(1 + rng() % 255);
    write_bytes(q, b);
    try {
      read_mvx_points(q);
    } catch (const Error&) {
    }
  }
  for (size_t n = 0; n < good.size(); n += 1499) {
    write_bytes(q, std::vector<char>(good.begin(), good.begin() + n));
    EXPECT_THROW(read_mvx_points(q), Error) << "truncated to " << n;
  }
  // Structure broken with valid checksums: the writer refuses, and so would the reader.
  auto expect_refused = [&](PointHierarchy bad, const std::string& words) {
    EXPECT_NE(error_message([&] { write_mvx_points(q, bad); }).find(words), std::string::npos) << words;
  };
  PointHierarchy bad = h;
  bad.nodes[1].code ^= 1;
  expect_refused(bad, "another code");
  bad = h;
  bad.points_kept += 1;
  expect_refused(bad, "kept");
  bad = h;
  bad.nodes.back().point_count += 1;
  expect_refused(bad, "node order");
  bad = h;
  bad.nodes_per_level.back() += 1;
  expect_refused(bad, "per level");
  fs::remove(p);
  fs::remove(q);
}

MV_INSTANTIATE_ON_ALL_DEVICES(MvxVersionTest);

}  // namespace
}  // namespace mv::test
