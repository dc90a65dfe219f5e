// megavox — surface voxelization (conservative or thin) of triangle meshes into sorted, unique Morton keys.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "megavox/device.h"
#include "megavox/grid.h"

namespace mv {

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
