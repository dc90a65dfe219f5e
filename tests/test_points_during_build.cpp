// Rendering while building: every checkpoint's forest is a valid partial hierarchy whose leaves hold exactly the
// points formed so far, and `render_during_build` writes its frames of the rendering front (test_omicron_front.cpp
// checks the front itself) with counts that never shrink when it draws every formed point.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "megavox/point_build.h"
#include "megavox/point_render.h"
#include "point_fixture.h"
#include "test_support.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;

class PointsDuringBuildTest : public ::testing::TestWithParam<DeviceInfo> {};

PointColumns sphere_cloud(uint64_t n) {
  std::mt19937_64 rng(21);
  std::normal_distribution<double> g(0, 1);
  PointColumns c;
  for (uint64_t i = 0; i < n; ++i) {
    double v[3] = {g(rng), g(rng), g(rng)};
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + 1e-9;
    for (double x : v) c.xyz.push_back(static_cast<int32_t>(x / len * 1e5));
  }
  return c;
}

TEST_P(PointsDuringBuildTest, EveryCheckpointIsAValidForest) {
  Device& dev = shared_device(GetParam());
  PointColumns cloud = sphere_cloud(20000);
  PointBuildOptions o;
  o.max_node_points = 300;
  o.prefix_points = 700;
  o.checkpoint_points = 2000;
  uint64_t last_formed = 0, checkpoints = 0;
  o.on_checkpoint = [&](const PointHierarchy& h, const std::vector<uint32_t>& roots) {
    ++checkpoints;
    EXPECT_GE(h.points_kept, last_formed);
    last_formed = h.points_kept;
    uint64_t rooted = 0, leaf_points = 0;
    for (uint32_t r : roots) rooted += h.nodes[r].subtree_points;
    EXPECT_EQ(rooted, h.points_kept) << "the roots' subtrees hold the formed points";
    std::vector<int> parents(h.nodes.size(), 0);
    for (size_t i = 0; i < h.nodes.size(); ++i) {
      const PointNode& n = h.nodes[i];
      if (n.leaf()) {
        leaf_points += n.point_count;
        continue;
      }
      uint32_t c = n.first_child;
      for (uint32_t oct = 0; oct < 8; ++oct)
        if (n.child_mask >> oct & 1) {
          ASSERT_LT(c, h.nodes.size());
          EXPECT_EQ(h.nodes[c].code, (n.code << 3) | oct);
          ++parents[c++];
        }
    }
    EXPECT_EQ(leaf_points, h.points_kept);
    for (uint32_t r : roots) parents[r] += 1;
    for (size_t i = 0; i < parents.size(); ++i) EXPECT_EQ(parents[i], 1) << "node " << i << " is in the forest once";
  };
  const uint64_t n = cloud.size();
  build_point_hierarchy(dev, std::move(cloud), PointCloudInfo(), o);
  EXPECT_GE(checkpoints, 5u);
  EXPECT_LT(last_formed, n);
}

TEST_P(PointsDuringBuildTest, FramesGrow) {
  Device& dev = shared_device(GetParam());
  // A PLY cloud on disk, as a user would hand it over.
  PointColumns cloud = sphere_cloud(30000);
  std::vector<points::PlyColumn> columns = {{"float", "x", {}}, {"float", "y", {}}, {"float", "z", {}}};
  for (uint64_t i = 0; i < cloud.size(); ++i)
    for (int a = 0; a < 3; ++a) columns[a].values.push_back(cloud.xyz[3 * i + a]);
  const std::string ply = temp_path("grow.ply");
  std::ofstream(ply, std::ios::binary) << points::make_cloud_ply(ply::Fmt::le, columns);
  const std::string dir = temp_path("frames");
  PointBuildOptions b;
  b.max_node_points = 500;
  PointRenderOptions r;
  r.width = 160;
  r.height = 120;
  r.lod_pixels = 0;  // the front draws every formed point (the CLI's default with --during-build)
  std::vector<BuildFrame> frames;
  render_during_build(dev, ply, dir, 5, b, r, [&](const BuildFrame& f) { frames.push_back(f); });
  ASSERT_EQ(frames.size(), 5u);
  for (size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(frames[k].frame, k);
    EXPECT_TRUE(fs::exists(frames[k].path)) << frames[k].path;
    EXPECT_GT(frames[k].front_nodes, 0u);
    if (k) {
      EXPECT_GE(frames[k].nodes, frames[k - 1].nodes);
      EXPECT_GE(frames[k].points_drawn, frames[k - 1].points_drawn);
    }
  }
  EXPECT_EQ(frames.back().points_drawn, 30000u);
  EXPECT_LT(frames.front().points_drawn, 30000u);

  // With a LOD rule the front coarsens as the render's cut does: the last frame is the finished cut.
  r.lod_pixels = 4;
  std::vector<BuildFrame> coarse;
  render_during_build(dev, ply, dir, 5, b, r, [&](const BuildFrame& f) { coarse.push_back(f); });
  ASSERT_EQ(coarse.size(), 5u);
  for (size_t k = 0; k < coarse.size(); ++k) EXPECT_LE(coarse[k].points_drawn, frames[k].points_drawn);
  EXPECT_LT(coarse.back().points_drawn, 30000u);
  try {
    render_during_build(dev, ply, dir, 0, b, r, {});
    ADD_FAILURE() << "no error for 0 frames";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the frame count"), std::string::npos) << e.what();
    EXPECT_EQ(e.settings, setting_frames);
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(PointsDuringBuildTest);

}  // namespace
}  // namespace mv::test
