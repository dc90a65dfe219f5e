// SymVox-family DAG files (SymVox v0.1, CRS4 2016; the voxcom tools of i3d2025-voxel-transform-dag write the
// 32-bit ones). Raw little-endian dumps, no magic number; the layout is told from the sizes it declares.
//
//   32-bit (.svdag, .ussvdag): float bbox_min[3], bbox_max[3], root_side; uint32 levels, nodes,
//       first_leaf, words; uint32 data[words]. Nodes level by level, root at word 0: a header word (child
//       mask in bits 0-7; .ussvdag: X, Y, Z mirror bits of child c at 8 + c, 16 + c, 24 + c) then one
//       absolute word index per child, children in descending c = 4x + 2y + z; the 2^3 masks (one word each)
//       from first_leaf on. An SVDAG is the mirror-free case of the same layout.
//   16-bit (.ssvdag): float bbox_min[3], bbox_max[3], root_side; uint32 levels, nodes; uint32 n; uint16
//       inner[n] (inner levels, root first); uint32 m; uint8 bricks[m] (8 bytes per 4^3 brick); uint32 k =
//       levels - 2; uint32 level_offset[k] (first 16-bit word of each inner level, root level first).
//       Nodes as megavox's ssvdag encoding (include/megavox/encode.h), which follows SymVox bit for bit.
//
// levels = log2(resolution). SymVox centres the root cube (side root_side) on the bbox's centre; voxcom
// writes voxel units (bbox from 0, cube at its min corner) and Morton child order x + 2y + 4z, which in
// this layout reads as the model with x and z swapped.
#pragma once
#include <cstdint>
#include <string>

#include "megavox/encode.h"

namespace mv::io {

struct SymvoxFile {
  float bbox_min[3] = {0, 0, 0}, bbox_max[3] = {0, 0, 0};
  float root_side = 0;
  uint32_t levels = 0;
  uint32_t nodes = 0;    // informational, as written
  EncodedDag dag;        // svdag / ussvdag words, or ssvdag inner + bricks; level offsets filled in
  uint64_t file_bytes = 0;
};

// Writes `file.dag` (svdag, ussvdag or ssvdag) with its header; to PATH.tmp, renamed on success.
void write_symvox(const std::string& path, const SymvoxFile& file);

// Reads and validates a SymVox-family file: layout from the content, level boundaries recovered from the
// pointers (32-bit) or the stored offsets (16-bit), then the encoding's full validation (sizes, pointers in
// range and one level down, so no cycles). Any fault is an mv::Error naming the file and what is wrong.
SymvoxFile read_symvox(const std::string& path);

}  // namespace mv::io
