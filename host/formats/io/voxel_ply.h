// Voxels as a PLY point cloud (`megavox export --format ply`): one vertex per voxel at its centre in model units,
// with its colour when there is one. Binary little endian, read by MeshLab and CloudCompare.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/grid.h"

namespace mv::io {

// keys: sorted voxel Morton codes of `grid`; rgb: 3 bytes per voxel, or empty (then no colour properties).
// Vertices: double x, y, z, then uchar red, green, blue. Written through a temporary name.
void write_voxel_ply(const std::string& path, const std::vector<uint64_t>& keys, const GridTransform& grid,
                     const std::vector<uint8_t>& rgb);

}  // namespace mv::io
