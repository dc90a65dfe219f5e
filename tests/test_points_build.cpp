// The point-cloud LOD build (host/core/points/) against its plain C++ references (host/ref/points_reference.h) and
// the OMiCroN oracles: every point once at the leaves, representatives copied from their subtree, codes
// consistent with their parents, the same bytes for every prefix size and device, and a valid cut after every
// step.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <tuple>

#include "megavox/point_build.h"
#include "points/omicron.h"
#include "points/omicron_representatives.h"
#include "points/point_kernels.h"
#include "points_reference.h"
#include "points_oracles.h"
#include "test_support.h"

namespace mv {
namespace {

using test::expect_same;
using test::expect_valid;
using test::shared_device;

class PointsBuildTest : public ::testing::TestWithParam<DeviceInfo> {};

// Clouds of different shapes: uniform, a thin sheet (a scan's surface), tight clusters with duplicates.
PointColumns make_cloud(const std::string& kind, uint64_t n, uint64_t seed, bool attributes) {
  std::mt19937_64 rng(seed);
  PointColumns c;
  for (uint64_t i = 0; i < n; ++i) {
    int32_t x, y, z;
    if (kind == "uniform") {
      std::uniform_int_distribution<int32_t> d(-1000000, 3000000);
      x = d(rng), y = d(rng), z = d(rng);
    } else if (kind == "sheet") {
      std::uniform_real_distribution<double> u(0, 1);
      const double a = u(rng), b = u(rng);
      x = static_cast<int32_t>(a * 50000), y = static_cast<int32_t>(b * 50000);
      z = static_cast<int32_t>(2000 * std::sin(a * 9) * std::cos(b * 7));
    } else {  // clusters: a few centres, points within a few units, many exact repeats
      std::uniform_int_distribution<int> centre(0, 4), off(-3, 3);
      const int k = centre(rng);
      x = k * 100000 + off(rng), y = -k * 7777 + off(rng), z = 5 + off(rng);
    }
    c.xyz.insert(c.xyz.end(), {x, y, z});
    if (attributes) {
      c.rgb.insert(c.rgb.end(), {static_cast<uint16_t>(i), static_cast<uint16_t>(i >> 16), 7});
      c.intensity.push_back(static_cast<uint16_t>(i * 31));
      c.normal.insert(c.normal.end(), {static_cast<float>(i), 0.5f, -1.0f});
    }
  }
  return c;
}

PointCloudInfo info_for(const PointColumns& c) {
  PointCloudInfo info;
  info.points = c.size();
  if (!c.rgb.empty()) info.attributes |= kPointRgb;
  if (!c.normal.empty()) info.attributes |= kPointNormal;
  if (!c.intensity.empty()) info.attributes |= kPointIntensity;
  return info;
}

TEST_P(PointsBuildTest, RepresentativesMatchTheReference) {
  Device& dev = shared_device(GetParam());
  std::mt19937_64 rng(11);
  for (int round = 0; round < 12; ++round) {
    // Groups of sorted codes, sizes from 1 to a few thousand, with repeats.
    std::vector<uint64_t> codes;
    std::vector<uint32_t> bounds{0};
    const int groups = 1 + static_cast<int>(rng() % 300);
    for (int g = 0; g < groups; ++g) {
      const uint64_t size = 1 + rng() % (round % 3 == 0 ? 4000 : 60);
      std::vector<uint64_t> c(size);
      const uint64_t mask = round % 2 ? (uint64_t{1} << 63) - 1 : 0xfff;
      for (auto& v : c) v = rng() & mask;
      std::sort(c.begin(), c.end());
      codes.insert(codes.end(), c.begin(), c.end());
      bounds.push_back(static_cast<uint32_t>(codes.size()));
    }
    const uint32_t cell_bits = 3 * static_cast<uint32_t>(rng() % 22);
    const uint32_t cap = 1 + static_cast<uint32_t>(rng() % 200);
    points::RepSelection got = points::select_representatives(dev, codes, bounds, cell_bits, cap);
    std::vector<uint32_t> want = ref::representatives(codes, bounds, cell_bits, cap);
    ASSERT_EQ(got.positions, want) << "round " << round << " cell_bits " << cell_bits << " cap " << cap;
    ASSERT_EQ(got.offsets.size(), bounds.size());
  }
}

// Parents far larger than one loop may run on lavapipe, one of them a single cell: the selection is spread over
// candidates, so they need no other path.
TEST_P(PointsBuildTest, ParentsOfHundredsOfThousandsOfCandidates) {
  Device& dev = shared_device(GetParam());
  std::mt19937_64 rng(5);
  std::vector<uint64_t> codes;
  std::vector<uint32_t> bounds{0};
  for (uint64_t mask : {(uint64_t{1} << 30) - 1, uint64_t{0}, uint64_t{0xffff}}) {
    std::vector<uint64_t> c(150000 + rng() % 1000);
    for (auto& v : c) v = (rng() & mask) | (uint64_t{bounds.size()} << 40);
    std::sort(c.begin(), c.end());
    codes.insert(codes.end(), c.begin(), c.end());
    bounds.push_back(static_cast<uint32_t>(codes.size()));
  }
  for (uint32_t cap : {1u, 300u, 100000u}) {
    points::RepSelection got = points::select_representatives(dev, codes, bounds, 12, cap);
    ASSERT_EQ(got.positions, ref::representatives(codes, bounds, 12, cap)) << "cap " << cap;
  }
}

TEST_P(PointsBuildTest, MatchesTheTopDownReference) {
  Device& dev = shared_device(GetParam());
  struct Case {
    std::string kind;
    uint64_t n;
    uint32_t depth, max_points;
  };
  for (const Case& c : {Case{"uniform", 20000, 6, 300}, Case{"sheet", 30000, 8, 500}, Case{"clusters", 5000, 21, 64},
                        Case{"uniform", 1, 4, 10}, Case{"sheet", 9, 3, 1}, Case{"clusters", 2000, 3, 5000}}) {
    SCOPED_TRACE(c.kind + " n=" + std::to_string(c.n));
    PointColumns cloud = make_cloud(c.kind, c.n, c.n + c.depth, true);
    const PointCloudInfo info = info_for(cloud);
    ref::PointLodRule rule{c.depth, c.max_points, 6};
    PointHierarchy want = ref::build_point_hierarchy(cloud, info, rule);
    PointBuildOptions options;
    options.depth = c.depth;
    options.max_node_points = c.max_points;
    options.prefix_points = 777;  // many steps: the cut advances through the stream
    PointColumns copy = cloud;
    PointHierarchy got = build_point_hierarchy(dev, std::move(copy), info, options);
    expect_same(got, want);
    expect_valid(got, cloud);
  }
}

// CPU devices sort the codes in place on the device (points::sorted_codes_in_place); a budget too small for
// that takes the host vectors' path (point_codes, then radix_sort in device-sized runs merged on the host):
// the same bytes either way.
TEST_P(PointsBuildTest, BothSortPathsGiveTheReference) {
  PointColumns cloud = make_cloud("sheet", 120000, 5, true);
  const PointCloudInfo info = info_for(cloud);
  ref::PointLodRule rule{7, 400, 6};
  const PointHierarchy want = ref::build_point_hierarchy(cloud, info, rule);
  PointBuildOptions options;
  options.depth = 7;
  options.max_node_points = 400;
  for (uint64_t budget : {uint64_t{0}, uint64_t{2} << 20}) {  // the default, then 2 MiB: under 24 B a point
    SCOPED_TRACE("device budget " + std::to_string(budget));
    auto dev = Device::open({GetParam().selector(), budget, false});
    if (budget == 0 && GetParam().type == "cpu") {
      points::SortedCodes sorted;
      ASSERT_TRUE(points::sorted_codes_in_place(*dev, cloud.xyz, points::cube_of(cloud.xyz), sorted));
      ASSERT_TRUE(std::is_sorted(sorted.codes.begin(), sorted.codes.end()));
    }
    if (budget != 0) {
      points::SortedCodes sorted;
      EXPECT_FALSE(points::sorted_codes_in_place(*dev, cloud.xyz, points::cube_of(cloud.xyz), sorted));
    }
    PointColumns copy = cloud;
    PointHierarchy got = build_point_hierarchy(*dev, std::move(copy), info, options);
    expect_same(got, want);
  }
}

// Where the hybrid sort runs in place (CPU devices without a loop cap), the builder takes its sorted prefixes
// while the later buckets still sort: several steps before the sort ends, and the reference's bytes.
TEST_P(PointsBuildTest, SortedPrefixesFeedTheBuilderWhileItSorts) {
  Device& dev = shared_device(GetParam());
  PointColumns cloud = make_cloud("uniform", 200000, 11, true);
  const PointCloudInfo info = info_for(cloud);
  const PointHierarchy want = ref::build_point_hierarchy(cloud, info, ref::PointLodRule{6, 300, 6});
  PointBuildOptions options;
  options.depth = 6;
  options.max_node_points = 300;
  PointBuildReport report;
  PointHierarchy got = build_point_hierarchy(dev, PointColumns(cloud), info, options, &report);
  expect_same(got, want);
  if (dev.host_view(dev.alloc(4, "probe")) && dev.info().max_loop_iterations == 0) {
    EXPECT_TRUE(report.sort.prefixes);
    EXPECT_GE(report.steps, 4u);  // one step per prefix: each is under the default step of 1M points
  }
}

TEST_P(PointsBuildTest, PrefixSizeDoesNotChangeTheBytes) {
  Device& dev = shared_device(GetParam());
  PointColumns cloud = make_cloud("sheet", 40000, 5, false);
  const PointCloudInfo info = info_for(cloud);
  PointHierarchy first;
  for (uint64_t prefix : {uint64_t{1} << 20, uint64_t{1}, uint64_t{13}, uint64_t{4096}}) {
    PointBuildOptions options;
    options.max_node_points = 1000;
    options.prefix_points = prefix;
    PointColumns copy = cloud;
    PointHierarchy h = build_point_hierarchy(dev, std::move(copy), info, options);
    if (prefix == uint64_t{1} << 20) {
      first = std::move(h);
      expect_valid(first, cloud);
    } else {
      SCOPED_TRACE("prefix " + std::to_string(prefix));
      expect_same(h, first);
    }
  }
}

// After every step the lists form an oblique cut: at most 7 roots per level, all siblings, all incomplete parents'
// children, and every node before the frontier has its parent.
TEST_P(PointsBuildTest, EveryCheckpointIsAValidCut) {
  Device& dev = shared_device(GetParam());
  PointColumns cloud = make_cloud("uniform", 12000, 9, false);
  points::PointCube cube = points::cube_of(cloud.xyz);
  std::vector<uint64_t> codes;
  std::vector<uint32_t> index;
  points::point_codes(dev, cloud.xyz, cube, codes, index);
  std::sort(codes.begin(), codes.end());
  points::OmicronRule rule{7, 200, 6};
  points::OmicronBuilder b(dev, rule);
  for (uint64_t end = 500;; end = std::min<uint64_t>(end + 500, codes.size())) {
    const bool last = end == codes.size();
    const uint64_t frontier = b.concatenate(std::span<const uint64_t>(codes.data(), end), last);
    for (uint32_t l = 1; l <= rule.depth; ++l) {
      const auto& list = b.level(l);
      const uint64_t roots = list.size() - b.first_root(l);
      ASSERT_LE(roots, 7u) << "level " << l << " at " << end;
      for (uint64_t r = b.first_root(l); r < list.size(); ++r) {
        EXPECT_EQ(list[r].prefix >> 3, list[b.first_root(l)].prefix >> 3) << "roots of level " << l << " are not siblings";
        // Their parent is not complete yet.
        const uint64_t parent = list[r].prefix >> 3;
        EXPECT_GT((parent + 1) << (3 * (rule.depth - l + 1)), frontier);
      }
    }
    if (last) {
      EXPECT_EQ(b.level(0).size(), 1u);
      break;
    }
  }
}

TEST_P(PointsBuildTest, RefusesBadOptions) {
  Device& dev = shared_device(GetParam());
  PointBuildOptions options;
  EXPECT_NE(test::error_message([&] { build_point_hierarchy(dev, PointColumns(), PointCloudInfo(), options); })
                .find("no points"),
            std::string::npos);
  options.depth = 22;
  EXPECT_NE(test::error_message([&] {
              build_point_hierarchy(dev, make_cloud("uniform", 10, 1, false), PointCloudInfo(), options);
            }).find("over 21"),
            std::string::npos);
}

TEST(PointsDepth, DensityRule) {
  EXPECT_EQ(point_depth_for(10, 16384), 2u);
  EXPECT_EQ(point_depth_for(100000000, 16384), 9u);
  EXPECT_EQ(point_depth_for(uint64_t{1} << 62, 1), 21u);
}

MV_INSTANTIATE_ON_ALL_DEVICES(PointsBuildTest);

}  // namespace
}  // namespace mv
