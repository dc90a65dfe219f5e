// Voxel colours of a mesh on the device (kernels/common/mesh_colour.h, docs/colour.md): each voxel takes the
// colour at the point nearest its centre on the triangles that overlap it (ties: the lowest triangle index),
// interpolated from the triangle's vertex colours; then the depth-first attribute array, inner nodes as means.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "megavox/bricks.h"
#include "megavox/device.h"
#include "io/mesh_source.h"
#include "megavox/voxelize.h"

namespace mv {

// What colours each triangle: its 3 vertex colours (0xBBGGRR; white where the mesh has none), its texture
// (io::kNoTexture: none) and its vertices' texture coordinates (6 floats, u v per vertex).
struct MeshTriangleColours {
  std::vector<uint32_t> rgb, texture;
  std::vector<float> uv;
  std::vector<io::MeshTexture> textures;
  std::vector<uint32_t> ordinal;  // out of core: each triangle's place in the file's triangles (coloured_records)
};

// `bricks`: the voxel set (Voxelizer::take_bricks) on a grid of 2^levels voxels; `fragments`: what the voxelizer met
// on its way (Voxelizer::record_fragments), whose triangle indices count in `tris`: every triangle the voxelizer
// took, in grid units (9 floats each), in its order, with its colours in `colours`. A textured triangle's colour at a
// point is its texture sampled bilinearly (repeating) at the interpolated coordinates; another's its vertex colours
// interpolated. Returns RGB24 per octree node in pre-order. Throws mv::Error when the voxels, fragments or
// triangles pass what one device call indexes (2^32 - 1), the textures one binding, or the sizes disagree.
// `batch_triangles`: triangles a device batch holds (0: what one binding holds).
std::vector<uint8_t> mesh_voxel_colours(Device& dev, const Bricks& bricks, const Fragments& fragments,
                                        std::span<const float> tris, const MeshTriangleColours& colours,
                                        uint32_t levels, uint64_t batch_triangles = 0);

// The voxels' own colours before the depth-first array: their sorted codes and 0xBBGGRR each, on the device.
struct MeshVoxelValues {
  Buffer keys, rgb;
  uint64_t voxels = 0;
};
// The same rule for the voxels `bricks` holds (an out-of-core build's cube: `tris` are the triangles its bucket
// holds, in the order of their indices in the mesh, which break ties). `colours.textures` is not read: `textures`
// are the mesh's.
MeshVoxelValues mesh_voxel_values(Device& dev, const Bricks& bricks, const Fragments& fragments,
                                  std::span<const float> tris, const MeshTriangleColours& colours,
                                  const std::vector<io::MeshTexture>& textures, uint64_t batch_triangles = 0);

// Out of core (build_pipeline.cpp), a coloured triangle travels through its cubes' buckets as one record: its 9
// floats, then its MV_MESH_ATTR_WORDS colour words (vertex colours, texture coordinates, texture) with its index in
// the mesh in the first spare one.
inline constexpr uint32_t kColourRecord = 21;

// The records of a batch of triangles (grid units) whose colours `c` holds (then cleared), from mesh index `first`.
void coloured_records(const std::vector<float>& tris, MeshTriangleColours& c, std::vector<float>& out);

// A cube's records back into its triangles (in `records`) and their colours (appended to `c`), in mesh order: the
// order that breaks ties.
void split_records(std::vector<float>& records, MeshTriangleColours& c);

// Every cube's voxels with their colours (both emptied), sorted by code on the device, into the depth-first array.
// Throws a CodedError naming `input` when they do not fit device memory (smaller cubes would not help).
std::vector<uint8_t> cube_colours_depth_first(Device& dev, const std::string& input, std::vector<uint64_t>& keys,
                                              std::vector<uint32_t>& rgb, uint32_t levels);

}  // namespace mv
