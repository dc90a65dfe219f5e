// The point content of .mvx (version 2): round trips of every column, files whose points other processes hold
// in part, version-1 voxel files still open, the kinds refuse each other, and damage (bytes, structure with
// valid checksums, truncation) is a clear error.
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

// The points at `index` of `from`, every column.
PointColumns points_at(const PointColumns& from, const std::vector<uint64_t>& index, uint32_t extra_bytes) {
  PointColumns out;
  for (uint64_t i : index) {
    out.xyz.insert(out.xyz.end(), from.xyz.begin() + 3 * i, from.xyz.begin() + 3 * i + 3);
    if (!from.rgb.empty()) out.rgb.insert(out.rgb.end(), from.rgb.begin() + 3 * i, from.rgb.begin() + 3 * i + 3);
    if (!from.normal.empty())
      out.normal.insert(out.normal.end(), from.normal.begin() + 3 * i, from.normal.begin() + 3 * i + 3);
    if (!from.intensity.empty()) out.intensity.push_back(from.intensity[i]);
    if (!from.extra.empty())
      out.extra.insert(out.extra.end(), from.extra.begin() + extra_bytes * i, from.extra.begin() + extra_bytes * (i + 1));
  }
  return out;
}

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

// A file whose points other processes hold in part (a build over ranks): the same bytes as the whole file.
TEST(MvxPoints, PointsHeldElsewhereWriteTheSameBytes) {
  for (bool attributes : {false, true}) {
    const PointHierarchy whole = sample_points(attributes);
    const std::string p = temp_path("points_whole.mvx"), q = temp_path("points_shared.mvx");
    write_mvx_points(p, whole);
    // Below level 2, the later half of each level's nodes is held elsewhere.
    PointsElsewhere share;
    share.elsewhere.assign(whole.nodes.size(), false);
    std::vector<uint64_t> seen(whole.depth + 1, 0);
    for (size_t i = 0; i < whole.nodes.size(); ++i) {
      const PointNode& n = whole.nodes[i];
      share.elsewhere[i] = n.level >= 2 && 2 * seen[n.level]++ >= whole.nodes_per_level[n.level];
    }
    PointHierarchy here = whole;
    here.points = PointColumns();
    std::vector<uint64_t> held;
    for (size_t i = 0; i < whole.nodes.size(); ++i)
      for (uint64_t k = 0; !share.elsewhere[i] && k < whole.nodes[i].point_count; ++k)
        held.push_back(whole.nodes[i].first_point + k);
    here.points = points_at(whole.points, held, whole.source.extra_bytes);
    uint64_t calls = 0;
    share.others = [&](PointColumn c, uint32_t level, const PutPointBytes& put) {
      ++calls;
      for (size_t i = 0; i < whole.nodes.size(); ++i) {
        const PointNode& n = whole.nodes[i];
        if (!share.elsewhere[i] || n.level != level) continue;
        const PointColumns& w = whole.points;
        const uint64_t f = n.first_point, k = n.point_count;
        switch (c) {
          case PointColumn::xyz: put(w.xyz.data() + 3 * f, 12 * k); break;
          case PointColumn::rgb: put(w.rgb.data() + 3 * f, 6 * k); break;
          case PointColumn::normal: put(w.normal.data() + 3 * f, 12 * k); break;
          case PointColumn::intensity: put(w.intensity.data() + f, 2 * k); break;
          case PointColumn::extra: put(w.extra.data() + 3 * f, 3 * k); break;
        }
      }
    };
    write_mvx_points(q, here, share);
    EXPECT_EQ(file_bytes(q), file_bytes(p)) << (attributes ? "with attributes" : "xyz alone");
    EXPECT_EQ(calls, (attributes ? 5u : 1u) * (whole.depth + 1));
    // A node held here after one held elsewhere on its level is refused.
    PointsElsewhere wrong = share;
    for (size_t i = whole.nodes.size(); i-- > 0;)
      if (whole.nodes[i].level == whole.depth) {
        wrong.elsewhere[i] = false;
        break;
      }
    EXPECT_NE(error_message([&] { write_mvx_points(q, here, wrong); }).find("follows nodes held elsewhere"),
              std::string::npos);
    fs::remove(p);
    fs::remove(q);
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
