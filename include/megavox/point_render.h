// megavox — pictures of a point hierarchy: an LOD cut chosen by screen-space size, drawn as depth-tested square
// splats by the splat kernels (kernels/common/splat.h), coloured and shaded (eye-dome lighting) on the host.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/points.h"
#include "megavox/render.h"

namespace mv {

class Device;  // megavox/device.h

struct PointRenderOptions {
  uint32_t width = 1280, height = 720;
  std::string view = "iso";  // front, back, left, right, top, iso
  char up = 0;               // 'x', 'y' or 'z'; 0: the file's (+Z for LAS input, +Y for PLY)
  double fov = 40;           // vertical, degrees
  double lod_pixels = 1.0;   // a node is drawn when its points' spacing projects to at most this many pixels
  uint32_t point_size = 3;   // splat side in pixels (odd; even sizes round up)
};

struct PointRenderResult {
  Image image;
  uint64_t nodes_drawn = 0, points_drawn = 0;
  uint64_t pixels_covered = 0;
  std::vector<uint32_t> depth, winner;  // per pixel: the splat kernels' depth key and winning point (cut order)
};

PointRenderResult render_points(Device& dev, const PointHierarchy& h, const PointRenderOptions& options);

}  // namespace mv
