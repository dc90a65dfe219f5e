// io::memory_files, the fuzz targets' seam (io/file_ops.h): a path put there is read from memory by megavox's
// own readers, with the same result as the file with those bytes, and is a missing file again once cleared.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/file_ops.h"
#include "io/mesh_source.h"
#include "io/mvx_pages.h"
#include "io/point_source.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "test_support.h"

namespace mv::test {
namespace {

std::string memfile_seed(const std::string& target, const std::string& name) {
  return std::string(MEGAVOX_SOURCE_DIR) + "/fuzz/corpus/" + target + "/" + name;
}

// Every point's position of a cloud, in reading order.
std::vector<float> memfile_cloud_positions(const std::string& path) {
  auto source = io::open_points(path, {});
  std::vector<float> xyz;
  PointColumns points;
  while (true) {
    points.clear();
    if (!source->next(points, 1000)) break;
    xyz.insert(xyz.end(), points.xyz.begin(), points.xyz.end());
  }
  return xyz;
}

// A mesh's positions and triangles, as open_mesh delivers them.
std::pair<std::vector<float>, std::vector<uint32_t>> memfile_mesh(const std::string& path) {
  auto mesh = io::open_mesh(path);
  std::vector<float> positions(mesh->positions().begin(), mesh->positions().end());
  std::vector<uint32_t> all, batch;
  while (mesh->next_triangles(batch, 100)) all.insert(all.end(), batch.begin(), batch.end());
  return {positions, all};
}

struct MemoryFileGuard {
  ~MemoryFileGuard() { io::memory_files::clear(); }
};

const std::string kMemfilePath = "/nonexistent-megavox-memory-file/input";

TEST(MemoryFiles, PointReadersReadTheBytesInPlaceOfThePath) {
  MemoryFileGuard guard;
  for (const std::string& file : {memfile_seed("fuzz_las", "las14_format6_wkt_evlr.las"), memfile_seed("fuzz_ply_points", "cloud_ascii.ply")}) {
    SCOPED_TRACE(file);
    const std::vector<char> bytes = file_bytes(file);
    const std::vector<float> expected = memfile_cloud_positions(file);
    ASSERT_FALSE(expected.empty());
    io::memory_files::put(kMemfilePath, bytes.data(), bytes.size());
    EXPECT_EQ(io::first_bytes(kMemfilePath, 4), std::string(bytes.data(), 4));
    EXPECT_EQ(io::read_whole_file(kMemfilePath), bytes);
    EXPECT_EQ(memfile_cloud_positions(kMemfilePath), expected);
  }
  io::memory_files::clear();
  EXPECT_THROW(io::first_bytes(kMemfilePath, 4), Error);
  EXPECT_THROW(memfile_cloud_positions(kMemfilePath), Error);
}

// assimp opens the file itself, through io::AssimpFiles: the memory file reaches it too.
TEST(MemoryFiles, MeshReadersReadTheBytes) {
  MemoryFileGuard guard;
  for (const std::string& file : {memfile_seed("fuzz_mesh_assimp", "quad_cube.obj"), memfile_seed("fuzz_ply_mesh", "pyramid_le.ply")}) {
    SCOPED_TRACE(file);
    const std::vector<char> bytes = file_bytes(file);
    const auto expected = memfile_mesh(file);
    ASSERT_FALSE(expected.second.empty());
    const std::string path = kMemfilePath + file.substr(file.size() - 4);  // assimp picks its importer by name
    io::memory_files::put(path, bytes.data(), bytes.size());
    EXPECT_EQ(memfile_mesh(path), expected);
  }
  io::memory_files::clear();
  EXPECT_THROW(memfile_mesh(kMemfilePath + ".obj"), Error);
}

TEST(MemoryFiles, MvxReadersAndTheMappedFileReadTheBytes) {
  MemoryFileGuard guard;
  const std::string file = memfile_seed("fuzz_mvx", "voxels_svdag.mvx");
  const std::vector<char> bytes = file_bytes(file);
  io::memory_files::put(kMemfilePath, bytes.data(), bytes.size());
  const io::MappedFile mapped(kMemfilePath);
  ASSERT_EQ(mapped.size(), bytes.size());
  EXPECT_EQ(static_cast<const void*>(mapped.data()), static_cast<const void*>(bytes.data()));  // in place
  EXPECT_EQ(read_mvx(kMemfilePath).dag.words, read_mvx(file).dag.words);
  const MvxPages from_memory(kMemfilePath), from_file(file);
  ASSERT_EQ(from_memory.pages(), from_file.pages());
  std::vector<uint32_t> a(from_memory.page_words()), b(from_file.page_words());
  for (uint32_t p = 0; p < from_file.pages(); ++p) {
    std::string error;
    ASSERT_TRUE(from_memory.read_page(p, a, &error)) << error;
    ASSERT_TRUE(from_file.read_page(p, b, &error)) << error;
    EXPECT_EQ(a, b);
  }
  // An empty memory file is an empty file, not a missing one.
  io::memory_files::put(kMemfilePath, nullptr, 0);
  EXPECT_TRUE(io::read_whole_file(kMemfilePath).empty());
  uint64_t size = 1;
  EXPECT_NE(io::open_regular(kMemfilePath, &size), nullptr);
  EXPECT_EQ(size, 0u);
}

}  // namespace
}  // namespace mv::test
