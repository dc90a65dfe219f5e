// megavox — plain grid types: model bounds, the world-to-grid transform and where the grid sits around a model.
// No device types: file readers and reference code use these alone.
#pragma once
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace mv {

struct Bounds {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity()};
  void extend(double x, double y, double z) {
    const double p[3] = {x, y, z};
    for (int a = 0; a < 3; ++a) {
      lo[a] = p[a] < lo[a] ? p[a] : lo[a];
      hi[a] = p[a] > hi[a] ? p[a] : hi[a];
    }
  }
  bool empty() const { return !(lo[0] <= hi[0]); }
};

// World -> grid: g = (p - origin) / voxel_size; voxel i covers [i, i+1) along each axis, and the grid's top
// face belongs to voxel resolution - 1.
struct GridTransform {
  double origin[3] = {0, 0, 0};
  double voxel_size = 1;
  uint32_t resolution = 1;  // voxels per axis, at most 2^21 (64-bit Morton keys)
};

// Where the grid's cube sits around a model.
//   center (the default): side = the longest extent of the bounds, the cube centred on the bounds (as the
//                         SymVox tools place it);
//   min:                  the same side, origin at the bounds' min corner, so shorter axes start at 0:
//                         p' = (p - min) * resolution / extent (the voxcom / cuda_voxelizer convention);
//   cube:                 an explicit cube (min corner, side), so several inputs share one grid; geometry
//                         outside it is cut away.
struct GridPlacement {
  enum class Origin { kCenter, kMin, kCube };
  Origin origin = Origin::kCenter;
  double corner[3] = {0, 0, 0};  // kCube only
  double side = 0;               // kCube only
};

// "center" | "min" -> a placement; anything else is an error naming the choices.
GridPlacement parse_grid_origin(const std::string& text);
// "X,Y,Z,SIZE" (the cube's min corner and side, in the model's units) -> an explicit cube.
GridPlacement parse_grid_bounds(const std::string& text);
std::string to_string(GridPlacement::Origin origin);

// The grid of `resolution` voxels per axis placed around `bounds`. With center or min, a flat or point-like
// model gets a side of at least one unit so the grid stays valid.
GridTransform grid_for_bounds(const Bounds& bounds, uint32_t resolution, const GridPlacement& placement = {});

// Appends the triangles (`indices` holds 3 per triangle into `positions`, 3 floats per vertex) in grid
// units, 9 floats per triangle, to `out`. With `clip` false (the grid was placed around these triangles)
// coordinates are clamped into [0, resolution], which only absorbs round-off. With `clip` true (an explicit
// cube) coordinates are kept and triangles whose bounding box misses the grid are dropped; the voxelizer's
// exact test cuts the rest at the grid's faces. `kept`, when given, receives the index (in `indices`) of each
// triangle appended.
void triangles_to_grid(const GridTransform& grid, std::span<const float> positions, const uint32_t* indices,
                       size_t triangles, std::vector<float>& out, bool clip = false,
                       std::vector<uint32_t>* kept = nullptr);

}  // namespace mv
