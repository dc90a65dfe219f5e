#include "io/memory_mesh.h"

#include <algorithm>
#include <cmath>

#include "megavox/error.h"

namespace mv::io {

namespace {

class MemoryMesh final : public MeshSource {
 public:
  MemoryMesh(std::span<const float> positions, std::span<const uint32_t> indices, std::span<const uint32_t> colours)
      : positions_(positions), indices_(indices), colours_(colours) {}
  std::span<const float> positions() const override { return positions_; }
  std::span<const uint32_t> vertex_colours() const override { return colours_; }
  uint64_t triangles_hint() const override { return indices_.size() / 3; }
  bool rewind() override {
    next_ = 0;
    return true;
  }
  bool next_triangles(std::vector<uint32_t>& indices, size_t max) override {
    const size_t n = std::min(max * 3, indices_.size() - next_);
    indices.assign(indices_.begin() + static_cast<std::ptrdiff_t>(next_),
                   indices_.begin() + static_cast<std::ptrdiff_t>(next_ + n));
    next_ += n;
    return n > 0;
  }

 private:
  std::span<const float> positions_;
  std::span<const uint32_t> indices_;
  std::span<const uint32_t> colours_;
  size_t next_ = 0;
};

}  // namespace

std::unique_ptr<MeshSource> memory_mesh(std::span<const float> positions, std::span<const uint32_t> indices,
                                        const std::string& label, std::span<const uint32_t> colours) {
  if (positions.size() % 3) throw Error(label + ": the vertex array holds " + std::to_string(positions.size()) + " floats, not 3 per vertex");
  if (indices.size() % 3) throw Error(label + ": the index array holds " + std::to_string(indices.size()) + " indices, not 3 per triangle");
  const uint64_t vertices = positions.size() / 3;
  if (vertices > UINT32_MAX) throw Error(label + ": over 2^32 vertices");
  if (!colours.empty() && colours.size() != vertices)
    throw Error(label + ": " + std::to_string(colours.size()) + " vertex colours for " + std::to_string(vertices) + " vertices");
  for (size_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(positions[i])) throw Error(label + ": vertex " + std::to_string(i / 3) + " is not finite");
  for (size_t i = 0; i < indices.size(); ++i)
    if (indices[i] >= vertices)
      throw Error(label + ": triangle " + std::to_string(i / 3) + " names vertex " + std::to_string(indices[i]) +
                  " of " + std::to_string(vertices));
  return std::make_unique<MemoryMesh>(positions, indices, colours);
}

}  // namespace mv::io
