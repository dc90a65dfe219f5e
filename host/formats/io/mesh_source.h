// Triangle meshes from any supported file, as vertex positions plus triangles delivered in batches.
// PLY goes through megavox's streaming reader (massive scans); OBJ, glTF, FBX, STL, ... through assimp,
// which loads the whole file (those formats are rarely massive).
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mv::io {

// A base-colour texture: texels 0xBBGGRR, rows top first.
struct MeshTexture {
  uint32_t width = 0, height = 0;
  std::vector<uint32_t> rgb;
};
inline constexpr uint32_t kNoTexture = 0xffffffffu;

class MeshSource {
 public:
  virtual ~MeshSource() = default;
  virtual std::span<const float> positions() const = 0;  // 3 floats per vertex
  virtual bool positions_mapped() const { return false; }  // in a mapped scratch file (over the RAM limit)
  virtual uint64_t triangles_hint() const = 0;               // for progress; may be approximate
  // Per vertex 0xBBGGRR (8-bit sRGB) when the mesh has vertex colours; empty otherwise.
  virtual std::span<const uint32_t> vertex_colours() const { return {}; }
  // Base-colour textures (assimp: a material's base-colour or diffuse map, embedded or a PNG / JPEG beside the
  // mesh), each vertex's texture (kNoTexture: none) and its texture coordinates (u, v; v = 0 at the image's
  // bottom); all empty without textures.
  virtual const std::vector<MeshTexture>& textures() const {
    static const std::vector<MeshTexture> none;
    return none;
  }
  virtual std::span<const uint32_t> vertex_textures() const { return {}; }
  virtual std::span<const float> vertex_uvs() const { return {}; }
  // Replaces `indices` with up to max_triangles triangles (3 indices each); false at the end.
  virtual bool next_triangles(std::vector<uint32_t>& indices, size_t max_triangles) = 0;
  // Starts the faces again from the first, without reading the file again, and returns true; false, changing
  // nothing, where this source streams its faces from the file (open it anew instead).
  virtual bool rewind() { return false; }
  // Before the first next_triangles: delivers only share `part` of `parts` of the faces (a build over ranks),
  // read by offset, and returns true; false, changing nothing, where the file cannot be read so (only binary
  // PLY triangles can: PlyMeshReader::select_faces). first_triangle() is then the share's first face.
  virtual bool select_face_share(int /*part*/, int /*parts*/) { return false; }
  virtual uint64_t first_triangle() const { return 0; }
  // Bytes of the file this source reads (with a share: the vertices and its faces); 0: unknown.
  virtual uint64_t bytes_spanned() const { return 0; }
  // A build over ranks reading the vertices in shares (open_mesh's defer_vertices; binary PLY): whether this
  // source opened without its vertices (positions() and vertex_colours() then stay empty), their count, a range
  // of them read by offset (3 floats each; with colours 3 channels each as stored, in colour_bits bits: 8 or 16,
  // 0 without colours).
  virtual bool vertices_deferred() const { return false; }
  virtual uint64_t vertex_count() const { return positions().size() / 3; }
  virtual void read_vertex_range(uint64_t first, uint64_t last, std::vector<float>& xyz, std::vector<uint16_t>& rgb);
  virtual int colour_bits() const { return vertex_colours().empty() ? 0 : 8; }
};

// Chooses the reader by content (a PLY starts with "ply\n"), else by assimp. Throws mv::Error naming the file
// and the fault. A PLY's vertex positions over `ram_bytes` go to a memory-mapped scratch file.
std::unique_ptr<MeshSource> open_mesh(const std::string& path, uint64_t ram_bytes = UINT64_MAX,
                                      bool defer_vertices = false);

}  // namespace mv::io
