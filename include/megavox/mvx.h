// megavox — the .mvx container: one encoded DAG with its grid, bounds and counts, or (version 2) one point
// cloud's LOD hierarchy.
//
// Little-endian. A 4 KiB header page: magic "MEGAVOX\x1a", version, encoding, levels, the world-to-grid
// transform (origin, voxel size, resolution), the content kind (version 2: 0 voxels, 1 points), the model's
// bounds, the voxel (or point) count, a table of up to 16 sections (kind, offset, bytes, XXH3-64 checksum) and
// the header's own XXH3-64. Sections start on 4 KiB boundaries (so a reader can mmap them).
// Voxels: counts (SVO and DAG nodes per level), level offsets, node words.
// Points: a meta section (grid, cube, counts, attributes, CRS), nodes per level, the node table (breadth-first,
// 40 bytes per node) and one section per point column in node order, so the top levels' points are a prefix
// of every column: a reader can stop after the levels it wants.
// Version 1 files (voxels) still open.
// Written to a temporary name and renamed on success; the reader checks every field, every checksum and
// the encoding itself before returning.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/encode.h"
#include "megavox/grid.h"
#include "megavox/points.h"

namespace mv {

struct MvxFile {
  GridTransform grid;
  Bounds bounds;  // of the input model, in its own units
  uint64_t voxels = 0;
  std::vector<uint64_t> svo_nodes;  // index = level (0 = voxels)
  std::vector<uint64_t> dag_nodes;  // index = level (0 = voxels)
  EncodedDag dag;
};

inline constexpr uint32_t kMvxVersion = 2;

enum class MvxContent { voxels, points };
// What a file holds, from its checked header alone.
MvxContent mvx_content(const std::string& path);

void write_mvx(const std::string& path, const MvxFile& file);
MvxFile read_mvx(const std::string& path);  // voxel content; a point file is an error that says so

void write_mvx_points(const std::string& path, const PointHierarchy& h);
// Checks every section and the hierarchy itself (codes, children, counts) before returning.
PointHierarchy read_mvx_points(const std::string& path);

std::string encoding_name(Encoding e);

}  // namespace mv
