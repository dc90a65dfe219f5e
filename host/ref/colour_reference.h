// Plain loops for voxel colours from points (host/core/megavox/colour.h), for tests to compare against: maps
// from codes to sums, a recursive pre-order walk. Shares no code with the kernels or the DAG.
#pragma once
#include <cstdint>
#include <map>
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

// The voxel colours of a mesh by the rule (docs/colour.md), plainly: for every triangle (grid units, 9 floats),
// every voxel ref::voxelize gives it alone; per voxel the triangle whose nearest point to the voxel's centre is
// nearest (squared distance in double; ties: the lower index), and the vertex colours (`tri_rgb`, 3 0xBBGGRR per
// triangle) interpolated at that point, rounded half up. Returns the voxels' sorted codes and their colours.
struct MeshVoxelColours {
  std::vector<uint64_t> keys;
  std::vector<uint32_t> rgb;
};
// With textures: `tri_tex` per triangle (0xffffffff: none) and `tri_uv` 6 floats (u v per vertex); a textured
// triangle's colour is its texture (`textures`: width, height, then 0xBBGGRR texels rows top first) sampled
// bilinearly, repeating, at the interpolated coordinates (v = 0 at the bottom row).
struct RefTexture {
  uint32_t width = 0, height = 0;
  std::vector<uint32_t> rgb;
};
MeshVoxelColours mesh_voxel_colours(const std::vector<float>& grid_tris, const std::vector<uint32_t>& tri_rgb,
                                    uint32_t resolution, const std::vector<uint32_t>& tri_tex = {},
                                    const std::vector<float>& tri_uv = {}, const std::vector<RefTexture>& textures = {});

// The colour of every octree node of a voxel set, looked up by cell: each node's pre-order index counted over the
// sorted voxel codes (a node comes just before the first voxel below it), then that entry of the depth-first
// colours. For the hit colours of ray traversal.
class NodeColours {
 public:
  NodeColours(const std::vector<uint64_t>& sorted_voxels, uint32_t levels, const std::vector<uint8_t>& rgb);
  // R | G << 8 | B << 16 | 255 << 24 of cell (x, y, z) of `level` (0 = voxels); 0 when the cell is empty.
  uint32_t at(uint32_t level, uint32_t x, uint32_t y, uint32_t z) const;

 private:
  std::vector<std::map<uint64_t, uint64_t>> index_;  // per level: code -> pre-order index
  const std::vector<uint8_t>& rgb_;
};

}  // namespace mv::ref
