// OpenVDB input: level sets give their surface voxels, fog volumes their voxels > 0, one VDB voxel each.
#include <openvdb/openvdb.h>
#include <openvdb/io/Stream.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "io/vdb_source.h"
#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "reference.h"
#include "test_support.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;

// A level-set sphere ("ball") and a fog volume ("density") with two voxels > 0, written to `path`; returns the
// sphere.
openvdb::FloatGrid::Ptr write_ball_and_fog(const std::string& path) {
  openvdb::initialize();
  auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(10.0f, openvdb::Vec3f(3, -2, 5), 0.5f);
  sphere->setName("ball");
  auto fog = openvdb::FloatGrid::create(0.0f);
  fog->setName("density");
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  fog->tree().setValue(openvdb::Coord(1, 2, 3), 0.5f);
  fog->tree().setValue(openvdb::Coord(-4, 2, 3), 1.0f);
  fog->tree().setValue(openvdb::Coord(0, 0, 0), 0.0f);  // active but not > 0: not a voxel
  openvdb::io::File(path).write({sphere, fog});
  return sphere;
}

// The sphere's surface voxels: within half of the 0.5 voxel size.
uint64_t surface_voxels(const openvdb::FloatGrid& sphere) {
  uint64_t n = 0;
  for (auto it = sphere.cbeginValueOn(); it; ++it)
    if (std::abs(*it) <= 0.25f) ++n;
  return n;
}

TEST(Vdb, LevelSetSurfaceAndFogVoxels) {
  const std::string path = temp_path("test.vdb");
  const uint64_t expect = surface_voxels(*write_ball_and_fog(path));
  io::VdbVoxels ball = io::read_vdb(path, "", 0);
  EXPECT_EQ(ball.grid_name, "ball");
  EXPECT_EQ(ball.grid_class, "level set");
  EXPECT_EQ(ball.keys.size(), expect);
  EXPECT_EQ(ball.grid.voxel_size, 0.5);
  EXPECT_EQ(ball.grid.resolution, 64u);  // the sphere spans about 41 voxels

  io::VdbVoxels d = io::read_vdb(path, "density", 0);
  EXPECT_EQ(d.grid_class, "fog volume");
  EXPECT_EQ(d.keys.size(), 2u);
  EXPECT_EQ(d.grid.resolution, 8u);
  EXPECT_EQ(d.index_min[0], -4);

  EXPECT_THROW(io::read_vdb(path, "nosuch", 0), Error);
  // Resampled to 16 voxels per axis: each voxel set when a surface voxel maps into it.
  io::VdbVoxels small = io::read_vdb(path, "ball", 16);
  EXPECT_EQ(small.grid.resolution, 16u);
  EXPECT_DOUBLE_EQ(small.grid.voxel_size, 0.5 * ball.extent / 16);
  std::vector<uint64_t> expect_small;
  for (uint64_t k : ball.keys) {
    uint64_t c[3] = {0, 0, 0};
    for (int b = 0; b < 21; ++b)
      for (int a = 0; a < 3; ++a) c[a] |= (k >> (3 * b + a) & 1) << b;
    expect_small.push_back(ref::morton3(uint32_t(c[0] * 16 / ball.extent), uint32_t(c[1] * 16 / ball.extent),
                                        uint32_t(c[2] * 16 / ball.extent), 21));
  }
  std::sort(expect_small.begin(), expect_small.end());
  expect_small.erase(std::unique(expect_small.begin(), expect_small.end()), expect_small.end());
  EXPECT_TRUE(small.keys == expect_small);
  EXPECT_LT(small.keys.size(), ball.keys.size());
  fs::remove(path);
}

class VdbTest : public ::testing::TestWithParam<DeviceInfo> {};

// Through the whole job: the file holds exactly the level set's surface voxels.
TEST_P(VdbTest, BuildKeepsTheLevelSetSurface) {
  const std::string path = temp_path("test.vdb");
  const uint64_t expect = surface_voxels(*write_ball_and_fog(path));
  BuildOptions o;
  o.input = path;
  o.output = temp_path("ball.mvx");
  o.encoding = Encoding::ssvdag;
  BuildReport r = build_mvx(shared_device(GetParam()), o);
  EXPECT_EQ(r.voxels, expect);
  EXPECT_TRUE(decode_encoded(read_mvx(o.output).dag) == io::read_vdb(path, "", 0).keys);
  fs::remove(o.output);
  fs::remove(path);
}

MV_INSTANTIATE_ON_ALL_DEVICES(VdbTest);

TEST(Vdb, DamagedFileIsAClearError) {
  const std::string path = temp_path("damaged.vdb");
  std::FILE* f = std::fopen(path.c_str(), "wb");
  const unsigned char head[] = {0x20, 0x42, 0x44, 0x56, 1, 2, 3, 4, 5, 6, 7, 8};
  std::fwrite(head, 1, sizeof head, f);
  std::fclose(f);
  EXPECT_TRUE(io::is_vdb(path));
  EXPECT_THROW(io::read_vdb(path, "", 0), Error);
  fs::remove(path);
}

TEST(Vdb, EveryPrefixOfAFileIsAClearError) {
  // A file cut anywhere: an mv::Error (never another exception, a hang, or a grid read from part of the file).
  const std::string path = temp_path("whole.vdb"), cut = temp_path("cut.vdb");
  write_ball_and_fog(path);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ASSERT_GT(bytes.size(), 1000u);
  const size_t step = bytes.size() / 97 + 1;
  for (size_t n = 0; n < bytes.size(); n += step) {
    std::ofstream(cut, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(n));
    EXPECT_THROW(io::read_vdb(cut, "density", 0), Error) << n << " of " << bytes.size() << " bytes";
  }
  fs::remove(path);
  fs::remove(cut);
}

TEST(Vdb, StreamWrittenFilesAndInstancesRead) {
  // io::Stream writes no grid offsets: the grids before the wanted one are read and dropped. A grid sharing
  // its tree with an earlier one is an instance: its tree comes from that grid.
  openvdb::initialize();
  auto fog = openvdb::FloatGrid::create(0.0f);
  fog->setName("density");
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  fog->tree().setValue(openvdb::Coord(1, 2, 3), 0.5f);
  fog->tree().setValue(openvdb::Coord(7, 2, 3), 1.0f);
  auto shared = fog->copyGrid();  // shares fog's tree
  shared->setName("copy");
  auto other = openvdb::MaskGrid::create();
  other->setName("mask");
  other->tree().setValueOn(openvdb::Coord(0, 0, 0));

  const std::string streamed = temp_path("streamed.vdb"), instanced = temp_path("instanced.vdb");
  {
    std::ofstream os(streamed, std::ios::binary);
    openvdb::io::Stream(os).write({other, fog});
  }
  io::VdbVoxels s = io::read_vdb(streamed, "density", 0);
  EXPECT_EQ(s.keys.size(), 2u);
  EXPECT_EQ(io::read_vdb(streamed, "", 0).grid_name, "mask");
  EXPECT_THROW(io::read_vdb(streamed, "nosuch", 0), Error);

  openvdb::io::File(instanced).write({fog, other, shared});
  io::VdbVoxels c = io::read_vdb(instanced, "copy", 0);
  EXPECT_EQ(c.grid_name, "copy");
  EXPECT_TRUE(c.keys == s.keys);
  fs::remove(streamed);
  fs::remove(instanced);
}

TEST(Vdb, SharedSamples) {
  MV_SKIP_WITHOUT_SHARED_DATA("openvdb_samples/sphere.vdb");
  MV_SKIP_WITHOUT_SHARED_DATA("openvdb_samples/smoke.vdb");
  io::VdbVoxels s = io::read_vdb(shared_data_file("openvdb_samples/sphere.vdb"), "", 0);
  EXPECT_EQ(s.grid_name, "ls_sphere");
  EXPECT_GT(s.keys.size(), 10000u);
  io::VdbVoxels smoke = io::read_vdb(shared_data_file("openvdb_samples/smoke.vdb"), "density", 0);
  EXPECT_EQ(smoke.grid_class, "fog volume");
  EXPECT_GT(smoke.keys.size(), 100000u);
}

}  // namespace
}  // namespace mv::test
