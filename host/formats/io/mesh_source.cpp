#include "io/mesh_source.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "io/assimp_files.h"
#include "io/ply_reader.h"
#include "io/file_ops.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

class PlySource final : public MeshSource {
 public:
  PlySource(const std::string& path, uint64_t ram_bytes) : reader_(path, ram_bytes) {}
  std::span<const float> positions() const override { return reader_.positions(); }
  bool positions_mapped() const override { return reader_.positions_mapped(); }
  uint64_t triangles_hint() const override { return reader_.info().faces; }
  bool next_triangles(std::vector<uint32_t>& indices, size_t max) override {
    return reader_.next_triangles(indices, max);
  }

 private:
  PlyMeshReader reader_;
};

// Every mesh of the scene, with its node transforms applied, as one triangle soup.
class AssimpSource final : public MeshSource {
 public:
  explicit AssimpSource(const std::string& path) {
    Assimp::Importer importer;
    auto* files = new AssimpFiles;  // the importer owns it
    importer.SetIOHandler(files);
    const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices);
    if (!files->error().empty()) throw Error(files->error());
    if (!scene || !scene->mRootNode)
      throw Error(path + ": cannot read the mesh (" + std::string(importer.GetErrorString()) + ")");
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
      const aiMesh* mesh = scene->mMeshes[m];
      if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      const auto base = static_cast<uint32_t>(positions_.size() / 3);
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D& p = mesh->mVertices[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
          throw Error(path + ": vertex " + std::to_string(v) + " of mesh " + std::to_string(m) + " is not finite");
        positions_.insert(positions_.end(), {p.x, p.y, p.z});
      }
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
        for (int k = 0; k < 3; ++k) indices_.push_back(base + face.mIndices[k]);
      }
    }
  }
  std::span<const float> positions() const override { return positions_; }
  uint64_t triangles_hint() const override { return indices_.size() / 3; }
  bool next_triangles(std::vector<uint32_t>& indices, size_t max) override {
    indices.clear();
    size_t n = std::min(max * 3, indices_.size() - next_);
    indices.assign(indices_.begin() + static_cast<std::ptrdiff_t>(next_),
                   indices_.begin() + static_cast<std::ptrdiff_t>(next_ + n));
    next_ += n;
    return n > 0;
  }

 private:
  std::vector<float> positions_;
  std::vector<uint32_t> indices_;
  size_t next_ = 0;
};

bool starts_with_ply(const std::string& path) {
  const std::string head = first_bytes(path, 4);
  return head.size() == 4 && head.compare(0, 3, "ply") == 0 && (head[3] == '\n' || head[3] == '\r');
}

}  // namespace

std::unique_ptr<MeshSource> open_mesh(const std::string& path, uint64_t ram_bytes) {
  if (starts_with_ply(path)) return std::make_unique<PlySource>(path, ram_bytes);
  return std::make_unique<AssimpSource>(path);
}

}  // namespace mv::io
