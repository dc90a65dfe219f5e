#include "voxel_ply.h"

#include <cstring>
#include <string>

#include "atomic_file.h"
#include "file_ops.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

uint32_t ply_voxel_axis(uint64_t code, int axis) {
  uint32_t v = 0;
  for (uint32_t b = 0; b < 21; ++b) v |= uint32_t(code >> (3 * b + axis) & 1) << b;
  return v;
}

}  // namespace

void write_voxel_ply(const std::string& path, const std::vector<uint64_t>& keys, const GridTransform& grid,
                     const std::vector<uint8_t>& rgb) {
  const bool colour = !rgb.empty();
  if (colour && rgb.size() != keys.size() * 3)
    throw Error(path + ": " + std::to_string(rgb.size()) + " colour bytes for " + std::to_string(keys.size()) + " voxels");
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment megavox voxel centres\nelement vertex " +
                       std::to_string(keys.size()) + "\nproperty double x\nproperty double y\nproperty double z\n";
  if (colour) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  header += "end_header\n";
  const size_t stride = 24 + (colour ? 3 : 0);
  write_atomically(path, [&](std::FILE* f) {
    if (!write_all(f, header.data(), header.size())) return false;
    std::vector<char> block;
    constexpr size_t kPlyBlock = 1 << 16;
    for (size_t i = 0; i < keys.size(); i += kPlyBlock) {
      const size_t n = std::min(kPlyBlock, keys.size() - i);
      block.resize(n * stride);
      for (size_t j = 0; j < n; ++j) {
        double c[3];
        for (int a = 0; a < 3; ++a)
          c[a] = grid.origin[a] + (double(ply_voxel_axis(keys[i + j], a)) + 0.5) * grid.voxel_size;
        std::memcpy(block.data() + j * stride, c, 24);
        if (colour) std::memcpy(block.data() + j * stride + 24, rgb.data() + 3 * (i + j), 3);
      }
      if (!write_all(f, block.data(), block.size())) return false;
    }
    return true;
  });
}

}  // namespace mv::io
