// Reference ray traversal: a flat, voxel-by-voxel DDA over a decoded voxel set, the oracle for the
// hierarchical DAG traversal kernel. It shares with the kernel only the definition of the event order
// (kernels/common/trace.h: mv_rcp, mv_cross, mv_before, mv_ray_entry - what "the ray crosses boundary b
// before boundary b'" means); the walk, the occupancy test and the level-of-detail rule are its own.
#pragma once
#include <cstdint>
#include <vector>

#include "common/trace.h"

namespace mv::ref {

// The occupied cells of every level of a voxel set (sorted Morton keys per level; level 0 = voxels).
class Occupancy {
 public:
  Occupancy(const std::vector<uint64_t>& voxels, uint32_t levels);
  uint32_t levels() const { return levels_; }
  bool full(uint32_t level, uint32_t x, uint32_t y, uint32_t z) const;

 private:
  uint32_t levels_;
  std::vector<std::vector<uint64_t>> keys_;
};

// The first hit of a ray given in root-cube coordinates ([0, 1)^3 = 2^levels voxels per axis), walking
// every voxel-sized cell along the ray; a full cell of level l stops the ray when l = 0 or, with proj > 0,
// when its side * proj < (the t at which the ray entered it) + ray.lod_t. `steps` counts voxel cells.
MvHit trace(const Occupancy& occ, const MvRay& ray, float proj);

}  // namespace mv::ref
