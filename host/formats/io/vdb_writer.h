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
// `rgb`, when not empty (3 bytes per key, R first), adds a Vec3s grid named "colour" beside it: each voxel's colour
// as stored (sRGB) over 255, at the same voxels and transform.
void write_voxel_grid(const std::string& path, const std::vector<uint64_t>& keys, const GridTransform& grid, bool nano,
                      const std::vector<uint8_t>& rgb = {});

}  // namespace mv::io
