// Plain loops for voxel colours from points (host/core/megavox/colour.h), for tests to compare against: maps
// from codes to sums, a recursive pre-order walk. Shares no code with the kernels or the DAG.
#pragma once
#include <cstdint>
#include <vector>

namespace mv::ref {

struct ColourNode {
  uint32_t level = 0;  // 0 = voxel
  uint64_t code = 0;   // Morton code at its level
  uint8_t rgb[3] = {0, 0, 0};
};

// x, y, z cells per point (levels bits each) and 0xBBGGRR per point: every octree node in pre-order (children
// by Morton octant), with its colour (a voxel: the rounded-half-up mean of its points; an inner node: of the
// voxel colours below it).
std::vector<ColourNode> preorder_colours(const std::vector<uint32_t>& cells, const std::vector<uint32_t>& rgb,
                                         uint32_t levels);

// The sorted unique voxel codes of those cells.
std::vector<uint64_t> cloud_voxel_keys(const std::vector<uint32_t>& cells);

}  // namespace mv::ref
