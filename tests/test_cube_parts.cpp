// The kept cubes of `build --resume` and the packed parts MPI ranks send (io/cube_parts.h): a DAG packs and
// unpacks to itself; a kept file comes back only for its own build and cube, and never when damaged.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "io/cube_parts.h"
#include "megavox/error.h"
#include "test_support.h"

namespace mv::test {
namespace {

Dag small_dag() {
  Dag d;
  d.levels = 2;
  d.symmetric = true;
  d.voxels = 9;
  d.svo_nodes = {9, 2, 1};
  d.level.resize(3);
  d.level[1].mask = {0x81, 0xff};
  d.level[2].mask = {0x03};
  d.level[2].first = {0};
  d.level[2].children = {0, 1};
  d.level[2].tags = {0, 5};
  return d;
}

void expect_same(const Dag& a, const Dag& b) {
  EXPECT_EQ(a.levels, b.levels);
  EXPECT_EQ(a.symmetric, b.symmetric);
  EXPECT_EQ(a.reduced, b.reduced);
  EXPECT_EQ(a.voxels, b.voxels);
  EXPECT_EQ(a.svo_nodes, b.svo_nodes);
  ASSERT_EQ(a.level.size(), b.level.size());
  for (size_t l = 0; l < a.level.size(); ++l) {
    EXPECT_EQ(a.level[l].mask, b.level[l].mask);
    EXPECT_EQ(a.level[l].first, b.level[l].first);
    EXPECT_EQ(a.level[l].children, b.level[l].children);
    EXPECT_EQ(a.level[l].tags, b.level[l].tags);
  }
}

TEST(CubeParts, ADagPacksAndUnpacksToItselfWithItsPayloadAfterIt) {
  const Dag d = small_dag();
  std::vector<uint8_t> bytes = io::pack_dag(d);
  expect_same(io::unpack_dag(bytes), d);
  const size_t packed = bytes.size();
  bytes.insert(bytes.end(), {1, 2, 3});
  size_t used = 0;
  expect_same(io::unpack_dag(bytes, &used), d);
  EXPECT_EQ(used, packed);
  EXPECT_THROW(io::unpack_dag(bytes), Error);  // without `used`, bytes past the DAG are an error
  for (size_t cut : {size_t{0}, size_t{5}, packed / 2, packed - 1}) {
    std::vector<uint8_t> short_bytes(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_THROW(io::unpack_dag(short_bytes), Error) << cut;
  }
}

TEST(CubeParts, AKeptCubeComesBackOnlyForItsBuildAndCubeAndWhole) {
  const std::string dir = temp_path("kept_cubes");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::vector<uint8_t> bytes = io::pack_dag(small_dag());
  io::write_cube_part(dir, 12, 777, bytes);
  EXPECT_FALSE(std::filesystem::exists(io::cube_part_path(dir, 12) + ".writing"));
  ASSERT_TRUE(io::read_cube_part(dir, 12, 777));
  EXPECT_EQ(*io::read_cube_part(dir, 12, 777), bytes);
  EXPECT_FALSE(io::read_cube_part(dir, 12, 778));  // another build
  EXPECT_FALSE(io::read_cube_part(dir, 13, 777));  // no file
  std::filesystem::copy_file(io::cube_part_path(dir, 12), io::cube_part_path(dir, 14));
  EXPECT_FALSE(io::read_cube_part(dir, 14, 777));  // the file of another cube
  const std::string path = io::cube_part_path(dir, 12);
  const auto size = std::filesystem::file_size(path);
  for (uint64_t at : {uint64_t{0}, uint64_t{9}, uint64_t{40}, size - 1}) {  // header and body
    io::write_cube_part(dir, 12, 777, bytes);
    std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
    f.seekg(static_cast<std::streamoff>(at));
    const char c = static_cast<char>(f.get() ^ 0x20);
    f.seekp(static_cast<std::streamoff>(at));
    f.put(c);
    f.close();
    EXPECT_FALSE(io::read_cube_part(dir, 12, 777)) << "a flipped byte at " << at;
  }
  io::write_cube_part(dir, 12, 777, bytes);
  std::filesystem::resize_file(path, size - 3);
  EXPECT_FALSE(io::read_cube_part(dir, 12, 777));  // cut short
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mv::test
