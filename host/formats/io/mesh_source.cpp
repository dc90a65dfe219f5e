#include "io/mesh_source.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "io/assimp_files.h"
#include "io/image_reader.h"
#include "io/ply_reader.h"
#include "io/file_ops.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

class PlySource final : public MeshSource {
 public:
  PlySource(const std::string& path, uint64_t ram_bytes, bool defer) : reader_(path, ram_bytes, defer) {}
  bool vertices_deferred() const override { return reader_.vertices_deferred(); }
  uint64_t vertex_count() const override { return reader_.info().vertices; }
  void read_vertex_range(uint64_t first, uint64_t last, std::vector<float>& xyz, std::vector<uint16_t>& rgb) override {
    reader_.read_vertex_range(first, last, xyz, rgb);
  }
  int colour_bits() const override { return reader_.colour_bits(); }
  std::span<const float> positions() const override { return reader_.positions(); }
  bool positions_mapped() const override { return reader_.positions_mapped(); }
  std::span<const uint32_t> vertex_colours() const override { return reader_.colours(); }
  uint64_t triangles_hint() const override { return reader_.info().faces; }
  bool select_face_share(int part, int parts) override {
    const uint64_t faces = reader_.info().faces;
    const uint64_t first = static_cast<uint64_t>((unsigned __int128)faces * part / parts);
    const uint64_t last = static_cast<uint64_t>((unsigned __int128)faces * (part + 1) / parts);
    if (!reader_.select_faces(first, last)) return false;
    first_ = first;
    return true;
  }
  uint64_t first_triangle() const override { return first_; }
  uint64_t bytes_spanned() const override { return reader_.bytes_spanned(); }
  bool next_triangles(std::vector<uint32_t>& indices, size_t max) override {
    return reader_.next_triangles(indices, max);
  }

 private:
  PlyMeshReader reader_;
  uint64_t first_ = 0;
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
      // A base-colour texture with texture coordinates: each vertex of this mesh samples it.
      const uint32_t texture = mesh->HasTextureCoords(0) ? texture_of(scene, mesh, path) : kNoTexture;
      if (texture != kNoTexture) {
        vertex_texture_.resize(base, kNoTexture);
        uvs_.resize(2 * size_t{base}, 0.0f);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
          vertex_texture_.push_back(texture);
          uvs_.insert(uvs_.end(), {mesh->mTextureCoords[0][v].x, mesh->mTextureCoords[0][v].y});
        }
      }
      // Vertex colours (the first set) as 8-bit sRGB, rounded; where some meshes have them, the others are white.
      if (mesh->HasVertexColors(0)) {
        colours_.resize(base, 0xffffffu);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
          const aiColor4D& c = mesh->mColors[0][v];
          auto byte = [](float x) { return uint32_t(std::lround(std::clamp(double(x), 0.0, 1.0) * 255.0)); };
          colours_.push_back(byte(c.r) | byte(c.g) << 8 | byte(c.b) << 16);
        }
      }
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
        for (int k = 0; k < 3; ++k) indices_.push_back(base + face.mIndices[k]);
      }
    }
    if (!colours_.empty()) colours_.resize(positions_.size() / 3, 0xffffffu);
    if (!vertex_texture_.empty()) {
      vertex_texture_.resize(positions_.size() / 3, kNoTexture);
      uvs_.resize(2 * (positions_.size() / 3), 0.0f);
    }
  }
  const std::vector<MeshTexture>& textures() const override { return textures_; }
  std::span<const uint32_t> vertex_textures() const override { return vertex_texture_; }
  std::span<const float> vertex_uvs() const override { return uvs_; }
  std::span<const float> positions() const override { return positions_; }
  std::span<const uint32_t> vertex_colours() const override { return colours_; }
  uint64_t triangles_hint() const override { return indices_.size() / 3; }
  bool rewind() override {
    next_ = 0;
    return true;
  }
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
  std::vector<uint32_t> colours_;  // per vertex 0xBBGGRR, or empty
  std::vector<MeshTexture> textures_;
  std::vector<std::string> texture_names_;  // what each of textures_ was read from, to read each once
  std::vector<uint32_t> vertex_texture_;    // per vertex, or empty
  std::vector<float> uvs_;                  // 2 per vertex, or empty

  // The base-colour (else diffuse) texture of `mesh`'s material, read once: embedded ("*N") or a file named
  // relative to the mesh's folder; kNoTexture when the material has none. A texture that cannot be read is an
  // error naming it.
  uint32_t texture_of(const aiScene* scene, const aiMesh* mesh, const std::string& mesh_path) {
    const aiMaterial* mat = scene->mMaterials[mesh->mMaterialIndex];
    aiString name;
    if (mat->GetTexture(aiTextureType_BASE_COLOR, 0, &name) != AI_SUCCESS &&
        mat->GetTexture(aiTextureType_DIFFUSE, 0, &name) != AI_SUCCESS)
      return kNoTexture;
    const std::string key = name.C_Str();
    for (uint32_t i = 0; i < texture_names_.size(); ++i)
      if (texture_names_[i] == key) return i;
    RasterImage image;
    if (const aiTexture* embedded = scene->GetEmbeddedTexture(name.C_Str())) {
      if (embedded->mHeight != 0)
        throw Error(mesh_path + ": embedded texture " + key + " is not a compressed image (PNG or JPEG)");
      image = decode_image({reinterpret_cast<const uint8_t*>(embedded->pcData), embedded->mWidth},
                           mesh_path + " texture " + key);
    } else {
      const size_t slash = mesh_path.rfind('/');
      image = read_image((slash == std::string::npos ? std::string() : mesh_path.substr(0, slash + 1)) + key);
    }
    MeshTexture t;
    t.width = image.width;
    t.height = image.height;
    t.rgb.resize(size_t{image.width} * image.height);
    const uint32_t shift = image.max_value > 255 ? 8 : 0;
    for (size_t p = 0; p < t.rgb.size(); ++p)
      for (uint32_t c = 0; c < 3; ++c) {
        const uint32_t v = image.samples[p * image.channels + (image.channels == 3 ? c : 0)] >> shift;
        t.rgb[p] |= std::min<uint32_t>(v, 255) << (8 * c);
      }
    textures_.push_back(std::move(t));
    texture_names_.push_back(key);
    return static_cast<uint32_t>(textures_.size() - 1);
  }
  std::vector<uint32_t> indices_;
  size_t next_ = 0;
};

bool starts_with_ply(const std::string& path) {
  const std::string head = first_bytes(path, 4);
  return head.size() == 4 && head.compare(0, 3, "ply") == 0 && (head[3] == '\n' || head[3] == '\r');
}

}  // namespace

std::unique_ptr<MeshSource> open_mesh(const std::string& path, uint64_t ram_bytes, bool defer_vertices) {
  if (starts_with_ply(path)) return std::make_unique<PlySource>(path, ram_bytes, defer_vertices);
  return std::make_unique<AssimpSource>(path);
}

void MeshSource::read_vertex_range(uint64_t, uint64_t, std::vector<float>&, std::vector<uint16_t>&) {
  throw Error("internal error: a mesh that read its vertices was asked for a range of them");
}

}  // namespace mv::io
