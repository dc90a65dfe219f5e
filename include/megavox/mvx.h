// megavox — the .mvx container: one encoded DAG with its grid, bounds and counts.
//
// Little-endian. A 4 KiB header page: magic "MEGAVOX\x1a", version, encoding, levels, the world-to-grid
// transform (origin, voxel size, resolution), the model's bounds, the voxel count, a table of up to 16
// sections (kind, offset, bytes, XXH3-64 checksum) and the header's own XXH3-64. Sections start on 4 KiB
// boundaries (so a reader can mmap them): counts (SVO and DAG nodes per level), level offsets, node words.
// Written to a temporary name and renamed on success; the reader checks every field, every checksum and
// the encoding itself before returning.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/encode.h"
#include "megavox/grid.h"

namespace mv {

struct MvxFile {
  GridTransform grid;
  Bounds bounds;  // of the input model, in its own units
  uint64_t voxels = 0;
  std::vector<uint64_t> svo_nodes;  // index = level (0 = voxels)
  std::vector<uint64_t> dag_nodes;  // index = level (0 = voxels)
  EncodedDag dag;
};

inline constexpr uint32_t kMvxVersion = 1;

void write_mvx(const std::string& path, const MvxFile& file);
MvxFile read_mvx(const std::string& path);

std::string encoding_name(Encoding e);

}  // namespace mv
