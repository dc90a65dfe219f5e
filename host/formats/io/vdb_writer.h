// Voxel sets as OpenVDB mask grids (.vdb) and NanoVDB grids (.nvdb).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/grid.h"

namespace mv::io {

// Writes sorted Morton keys as a grid named "voxels": active voxel (x, y, z) in index space, the transform
// placing its centre at origin + (i + 1/2) * voxel_size, so megavox and OpenVDB agree on where voxels are.
// `nano`: a NanoVDB grid (ValueMask) instead of an OpenVDB MaskGrid. To PATH.tmp, renamed on success.
void write_voxel_grid(const std::string& path, const std::vector<uint64_t>& keys, const GridTransform& grid, bool nano);

}  // namespace mv::io
