// megavox — surface voxelization (conservative or thin) of triangle meshes into sorted, unique Morton keys.
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <span>
#include <vector>

#include "megavox/device.h"

namespace mv {

struct Bounds {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity()};
  void extend(double x, double y, double z);
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
// exact test cuts the rest at the grid's faces.
void triangles_to_grid(const GridTransform& grid, std::span<const float> positions, const uint32_t* indices,
                       size_t triangles, std::vector<float>& out, bool clip = false);

// Voxelizes triangle batches on a device, within its memory budget, and collects the voxels.
class Voxelizer {
 public:
  enum class Rule { kConservative, kThin };  // 26-separating exact overlap, or 6-separating (thin)
  Voxelizer(Device& dev, uint32_t resolution, Rule rule = Rule::kConservative);
  // Keeps only the voxels of the cube [x, x + size) x [y, y + size) x [z, z + size) (out-of-core builds
  // voxelize one such cube at a time). Default: the whole grid.
  void restrict_to(uint32_t x, uint32_t y, uint32_t z, uint32_t size);
  // Host bytes the collected keys (and the merge that grows them) may take; past it, add() throws an
  // mv::Error naming the need. 0 = no limit.
  void limit_host_memory(uint64_t bytes) { host_budget_ = bytes; }
  // Triangles in grid units (9 floats each), e.g. from triangles_to_grid.
  void add(const std::vector<float>& grid_triangles);
  // Sorted, unique 64-bit Morton keys of every voxel an added triangle meets; resets the collection.
  std::vector<uint64_t> take_keys();
  uint64_t triangles() const { return triangles_; }
  uint64_t hits() const { return hits_; }  // voxel hits before removing repeats

 private:
  void merge(std::vector<uint64_t>&& sorted_unique);
  Device& dev_;
  uint32_t resolution_;
  Rule rule_;
  uint32_t box_[3] = {0, 0, 0};
  uint32_t box_size_;
  uint64_t triangles_ = 0;
  uint64_t hits_ = 0;
  uint64_t host_budget_ = 0;
  std::vector<uint64_t> keys_;
};

}  // namespace mv
