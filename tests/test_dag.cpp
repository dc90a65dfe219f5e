// SVO levels and DAG reduction on every device against the map-based reference; decoding gives the voxels.
#include <algorithm>
#include <initializer_list>
#include <random>

#include "reference.h"
#include "common/ssvdag.h"
#include "megavox/dag.h"
#include "megavox/encode.h"
#include "megavox/voxelize.h"
#include "megavox/error.h"
#include "test_support.h"

namespace mv::test {
namespace {

class DagTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(DagTest, CountsMatchReferenceAndDecodeGivesTheVoxels) {
  Device& dev = shared_device(GetParam());
  for (uint32_t levels : {1u, 3u, 6u}) {
    for (auto& [name, voxels] : voxel_sets(levels)) {
      SCOPED_TRACE(name + ", levels " + std::to_string(levels));
      Dag dag = build_svdag(dev, voxels, levels);
      ref::DagCounts expect = ref::dag_counts(voxels, levels);
      EXPECT_EQ(dag.svo_nodes, expect.svo);
      for (uint32_t l = 1; l <= levels; ++l) {
        EXPECT_EQ(dag.nodes(l), expect.dag[l]) << "level " << l;
        EXPECT_LE(dag.nodes(l), dag.svo_nodes[l]) << "level " << l;
      }
      EXPECT_EQ(dag.nodes(levels), 1u);
      EXPECT_TRUE(decode_voxels(dag) == voxels);
    }
  }
}

TEST_P(DagTest, SymmetricCountsMatchReferenceAndDecodeGivesTheVoxels) {
  Device& dev = shared_device(GetParam());
  for (uint32_t levels : {1u, 3u, 6u}) {
    for (auto& [name, voxels] : voxel_sets(levels)) {
      SCOPED_TRACE(name + ", levels " + std::to_string(levels));
      Dag plain = build_svdag(dev, voxels, levels);
      Dag sym = build_ssvdag(dev, voxels, levels);
      ref::DagCounts expect = ref::ssvdag_counts(voxels, levels);
      EXPECT_EQ(sym.svo_nodes, expect.svo);
      for (uint32_t l = 1; l <= levels; ++l) {
        EXPECT_EQ(sym.nodes(l), expect.dag[l]) << "level " << l;
        EXPECT_LE(sym.nodes(l), plain.nodes(l)) << "level " << l;
      }
      EXPECT_TRUE(decode_voxels(sym) == voxels);
    }
  }
}

// The notes' synthetic case: two voxels mirrored across the grid's centre plane x = N/2. The SVDAG needs two
// nodes per level below the root (2L - 1), the SSVDAG one (L).
TEST_P(DagTest, TwoMirroredVoxels) {
  Device& dev = shared_device(GetParam());
  for (uint32_t levels : {2u, 5u, 9u}) {
    const uint32_t n = 1u << levels;
    std::vector<uint64_t> voxels = {ref::morton3(0, 3 % n, 1 % n, 21), ref::morton3(n - 1, 3 % n, 1 % n, 21)};
    std::sort(voxels.begin(), voxels.end());
    Dag plain = build_svdag(dev, voxels, levels);
    Dag sym = build_ssvdag(dev, voxels, levels);
    uint64_t plain_nodes = 0, sym_nodes = 0;
    for (uint32_t l = 1; l <= levels; ++l) {
      plain_nodes += plain.nodes(l);
      sym_nodes += sym.nodes(l);
    }
    EXPECT_EQ(plain_nodes, 2 * levels - 1) << "levels " << levels;
    EXPECT_EQ(sym_nodes, levels) << "levels " << levels;
    EXPECT_TRUE(decode_voxels(sym) == voxels);
  }
}

TEST_P(DagTest, EmptyInputGivesAnEmptyDag) {
  Dag dag = build_svdag(shared_device(GetParam()), std::vector<uint64_t>{}, 4);
  EXPECT_EQ(dag.voxels, 0u);
  EXPECT_TRUE(decode_voxels(dag).empty());
}

TEST_P(DagTest, VoxelizedMeshEndToEnd) {
  Device& dev = shared_device(GetParam());
  // An octahedron: 8 triangles, voxelized at 64^3, then reduced.
  std::vector<float> tris = octahedron_grid_triangles(64);
  Voxelizer v(dev, 64);
  v.add(tris);
  std::vector<uint64_t> voxels = v.take_keys();
  ASSERT_GT(voxels.size(), 1000u);
  Dag dag = build_svdag(dev, voxels, 6);
  ref::DagCounts expect = ref::dag_counts(voxels, 6);
  for (uint32_t l = 1; l <= 6; ++l) EXPECT_EQ(dag.nodes(l), expect.dag[l]) << "level " << l;
  EXPECT_TRUE(decode_voxels(dag) == voxels);
  Dag sym = build_ssvdag(dev, voxels, 6);
  ref::DagCounts sym_expect = ref::ssvdag_counts(voxels, 6);
  for (uint32_t l = 1; l <= 6; ++l) EXPECT_EQ(sym.nodes(l), sym_expect.dag[l]) << "level " << l;
  EXPECT_LT(sym.nodes(2), dag.nodes(2));  // the octahedron is symmetric: the SSVDAG must find it
  EXPECT_TRUE(decode_voxels(sym) == voxels);
}

// Level 2's exact keys: reflecting a 4x4x4 brick by T moves bit 8c + c' to 8(c ^ T) + (c' ^ T), and the
// 2x2x2 masks by T move bit c to c ^ T (written here from that definition, bit by bit).
TEST(DagBuild, BrickAndMaskReflectionsMoveEveryBit) {
  std::mt19937_64 rng(7);
  for (int k = 0; k < 200; ++k) {
    const uint64_t b = rng();
    for (uint32_t t = 0; t < 8; ++t) {
      uint64_t expect = 0;
      for (uint32_t bit = 0; bit < 64; ++bit)
        if (b >> bit & 1) expect |= uint64_t{1} << (bit ^ (t | t << 3));
      ASSERT_EQ(mv_reflect_brick(b, t), expect) << "T = " << t;
      uint32_t mask = static_cast<uint32_t>(b & 0xff), mexpect = 0;
      for (uint32_t c = 0; c < 8; ++c)
        if (mask >> c & 1) mexpect |= 1u << (c ^ t);
      ASSERT_EQ(mv_reflect_mask(mask, t), mexpect) << "T = " << t;
    }
  }
}

TEST_P(DagTest, RejectsKeysOutsideTheGrid) {
  EXPECT_THROW(build_svdag(shared_device(GetParam()), {ref::morton3(8, 0, 0, 21)}, 3), Error);
}

MV_INSTANTIATE_ON_ALL_DEVICES(DagTest);

}  // namespace
}  // namespace mv::test

namespace mv::test {
namespace {

// The voxels of each cube of `tris` on an n^3 grid, voxelized on demand as the out-of-core builds ask.
CubeVoxels voxelized_cubes(Device& dev, uint32_t n, const std::vector<float>& tris) {
  return [&dev, n, &tris](uint32_t x, uint32_t y, uint32_t z, uint32_t size) {
    Voxelizer v(dev, n);
    v.restrict_to(x, y, z, size);
    v.add(tris);
    return v.take_bricks();
  };
}

// Out-of-core (cube by cube, then merged) gives the in-core DAG exactly: the same encoded bytes, on an
// octahedron at 2^levels for each cube size, plain and symmetric.
void expect_out_of_core_equals_in_core(Device& dev, uint32_t levels, std::initializer_list<uint32_t> cube_sizes) {
  const uint32_t n = 1u << levels;
  std::vector<float> tris = octahedron_grid_triangles(n, -1.3f);
  CubeVoxels cube = voxelized_cubes(dev, n, tris);
  std::vector<uint64_t> voxels = keys_from_bricks(cube(0, 0, 0, n));
  for (bool symmetric : {false, true}) {
    Dag in_core = symmetric ? build_ssvdag(dev, voxels, levels) : build_svdag(dev, voxels, levels);
    for (uint32_t cube_levels : cube_sizes) {
      SCOPED_TRACE((symmetric ? "symmetric, cubes of 2^" : "plain, cubes of 2^") + std::to_string(cube_levels));
      Dag ooc = build_dag_by_cubes(dev, levels, cube_levels, symmetric, cube);
      EXPECT_EQ(ooc.voxels, in_core.voxels);
      EXPECT_EQ(ooc.svo_nodes, in_core.svo_nodes);
      EXPECT_TRUE(encode_svdag(ooc).words == encode_svdag(in_core).words);
      if (symmetric) {
        EXPECT_TRUE(encode_ssvdag(ooc).inner == encode_ssvdag(in_core).inner);
        EXPECT_TRUE(encode_ssvdag(ooc).bricks == encode_ssvdag(in_core).bricks);
      }
      EXPECT_TRUE(decode_voxels(ooc) == voxels);
    }
  }
}

TEST_P(DagTest, OutOfCoreEqualsInCore) { expect_out_of_core_equals_in_core(shared_device(GetParam()), 7, {4u, 6u}); }

// The smallest cubes: one brick each (roots at level 2, the octree above them starts at the bricks) and 2^3.
TEST_P(DagTest, OutOfCoreTinyCubesEqualInCore) {
  expect_out_of_core_equals_in_core(shared_device(GetParam()), 4, {2u, 3u});
}

// The plain octree out of core: the same levels, node for node, as in core.
TEST_P(DagTest, OctreeOutOfCoreEqualsInCore) {
  Device& dev = shared_device(GetParam());
  const uint32_t levels = 6, n = 1u << levels;
  std::vector<float> tris = octahedron_grid_triangles(n, -1.3f);
  CubeVoxels cube = voxelized_cubes(dev, n, tris);
  Dag in_core = build_svo(dev, cube(0, 0, 0, n), levels);  // the whole grid as one cube
  for (uint32_t cube_levels : {3u, 5u}) {
    Dag ooc = build_svo_by_cubes(dev, levels, cube_levels, cube);
    EXPECT_FALSE(ooc.reduced);
    EXPECT_EQ(ooc.svo_nodes, in_core.svo_nodes);
    EXPECT_TRUE(encode_svdag(ooc).words == encode_svdag(in_core).words) << "cubes of 2^" << cube_levels;
  }
}

}  // namespace
}  // namespace mv::test

namespace mv::test {
namespace {

TEST_P(DagTest, PlainOctreeEncodesAsSvo) {
  Device& dev = shared_device(GetParam());
  for (auto& [name, voxels] : voxel_sets(5)) {
    SCOPED_TRACE(name);
    Dag svo = build_svo(dev, voxels, 5);
    for (uint32_t l = 1; l <= 5; ++l) EXPECT_EQ(svo.nodes(l), svo.svo_nodes[l]) << "level " << l;
    EncodedDag enc = encode_svdag(svo);
    EXPECT_EQ(enc.encoding, Encoding::svo);
    EXPECT_TRUE(decode_svdag(enc) == voxels);
    EXPECT_GE(enc.words.size(), encode_svdag(build_svdag(dev, voxels, 5)).words.size());
  }
}

}  // namespace
}  // namespace mv::test
