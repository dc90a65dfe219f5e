// A point cloud as `megavox build` input: which files are clouds, and their points in world units with 8-bit
// colours. Internal to host/io and the build.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/grid.h"

namespace mv::io {

// A LAS file, or a PLY whose header declares vertices and no faces (or zero faces): a cloud to voxelize.
bool is_point_cloud(const std::string& path);

struct CloudPoints {
  std::string format;             // as point readers describe it: "LAS 1.2, point format 3", ...
  std::vector<double> xyz;        // 3 per point, world units (offset + scale * stored integer)
  std::vector<uint32_t> rgb;      // 0xBBGGRR per point, 8-bit channels; empty when the cloud has no colour
  bool wide_colour = false;       // the stored channels passed 255, so their high bytes were kept
  Bounds bounds;
};

// Reads every point (held in memory: about 34 bytes per point with colour). Stored 16-bit channels keep their high byte unless
// every value of the cloud fits 8 bits; `colour` false skips the colour. Throws mv::Error naming the file.
CloudPoints read_cloud(const std::string& path, bool colour);

}  // namespace mv::io
