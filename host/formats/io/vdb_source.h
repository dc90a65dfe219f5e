// OpenVDB grids as voxel sets: one VDB voxel = one megavox voxel, index space kept.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/grid.h"

namespace mv::io {

struct VdbVoxels {
  std::string grid_name, grid_class;  // class: "level set", "fog volume" (other float grids read as fog) or "mask"
  std::vector<uint64_t> keys;         // sorted unique Morton keys of (index - index_min)
  int64_t index_min[3] = {0, 0, 0};   // the smallest index of a selected voxel
  uint32_t extent = 0;                // voxels along the longest axis of the selected voxels' index box
  GridTransform grid;                 // world placement: voxel i covers [i, i+1) of the grid
  Bounds bounds;                      // world bounds of the selected voxels
};

// True when the file starts with OpenVDB's magic number.
bool is_vdb(const std::string& path);

// Reads grid `name` (empty: the first) of a .vdb file. Level sets give their surface voxels (active voxels
// with |distance| <= half a voxel); fog volumes and other float grids give their active voxels with value > 0;
// mask and bool grids (e.g. `megavox export --format vdb`) their active (true) voxels.
// The grid is resolution voxels per axis (0: the smallest power of two, at least 8, that holds the voxels);
// below the voxels' extent the grid is resampled (a voxel is set when any selected VDB voxel falls in it).
VdbVoxels read_vdb(const std::string& path, const std::string& name, uint32_t resolution);

}  // namespace mv::io
