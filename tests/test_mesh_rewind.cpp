// Mesh sources walked twice: a build surveys a mesh's faces, then voxelizes them (host/core/voxel/build_pipeline.cpp).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/memory_mesh.h"
#include "io/mesh_source.h"

namespace mv::test {
namespace {

std::string seed(const std::string& target, const std::string& name) {
  return std::string(MEGAVOX_SOURCE_DIR) + "/fuzz/corpus/" + target + "/" + name;
}

// A build walks a mesh's faces twice (the survey, then the voxels): sources holding their faces start again
// without reading the file; a PLY, which streams them, says it cannot, and goes on unchanged.
TEST(MeshSources, RewindWhereTheyHoldTheirFaces) {
  auto faces = [](io::MeshSource& mesh) {
    std::vector<uint32_t> all, batch;
    while (mesh.next_triangles(batch, 7)) all.insert(all.end(), batch.begin(), batch.end());
    return all;
  };
  auto obj = io::open_mesh(seed("fuzz_mesh_assimp", "quad_cube.obj"));
  const std::vector<uint32_t> first = faces(*obj);
  ASSERT_FALSE(first.empty());
  ASSERT_TRUE(obj->rewind());
  EXPECT_EQ(faces(*obj), first);
  const std::vector<float> xyz(obj->positions().begin(), obj->positions().end());
  auto memory = io::memory_mesh(xyz, first, "arrays");
  EXPECT_EQ(faces(*memory), first);
  ASSERT_TRUE(memory->rewind());
  EXPECT_EQ(faces(*memory), first);
  auto ply = io::open_mesh(seed("fuzz_ply_mesh", "pyramid_le.ply"));
  std::vector<uint32_t> batch;
  ASSERT_TRUE(ply->next_triangles(batch, 1));
  const std::vector<uint32_t> head = batch;
  EXPECT_FALSE(ply->rewind());
  std::vector<uint32_t> rest = faces(*ply);
  rest.insert(rest.begin(), head.begin(), head.end());
  EXPECT_EQ(rest, faces(*io::open_mesh(seed("fuzz_ply_mesh", "pyramid_le.ply"))));
}

}  // namespace
}  // namespace mv::test
