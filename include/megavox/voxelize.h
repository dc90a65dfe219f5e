// megavox — conservative surface voxelization of triangle meshes into sorted, unique Morton keys.
#pragma once
#include <cstdint>
#include <limits>
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

// The default placement: a cube whose side is the longest extent of `bounds`, centred on the bounds (as the
// SymVox tools place it), split into `resolution` voxels per axis. A flat or point-like model gets a side
// of at least one unit so the grid stays valid.
GridTransform grid_for_bounds(const Bounds& bounds, uint32_t resolution);

// Appends the triangles (`indices` holds 3 per triangle into `positions`, 3 floats per vertex) in grid
// units, 9 floats per triangle, to `out`. Coordinates are clamped into [0, resolution].
void triangles_to_grid(const GridTransform& grid, const std::vector<float>& positions,
                       const uint32_t* indices, size_t triangles, std::vector<float>& out);

// Voxelizes triangle batches on a device, within its memory budget, and collects the voxels.
class Voxelizer {
 public:
  Voxelizer(Device& dev, uint32_t resolution);
  // Keeps only the voxels of the cube [x, x + size) x [y, y + size) x [z, z + size) (out-of-core builds
  // voxelize one such cube at a time). Default: the whole grid.
  void restrict_to(uint32_t x, uint32_t y, uint32_t z, uint32_t size);
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
  uint32_t box_[3] = {0, 0, 0};
  uint32_t box_size_;
  uint64_t triangles_ = 0;
  uint64_t hits_ = 0;
  std::vector<uint64_t> keys_;
};

}  // namespace mv
