// megavox — surface voxelization (conservative or thin) of triangle meshes into 4^3 bricks (megavox/bricks.h).
#pragma once
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "megavox/bricks.h"
#include "megavox/device.h"
#include "megavox/grid.h"

namespace mv {

// Voxelizes triangle batches on a device, within its memory budget, and collects the voxels.
// Brick columns one voxelizer work item walks at most (256 voxel columns).
inline constexpr uint32_t kVoxelizeColumnsPerItem = 16;

// The voxelizer's work items for triangles in grid units (9 floats each): a triangle and its first brick column,
// per run of at most kVoxelizeColumnsPerItem columns of its walk, with a guess of the bricks it meets; only the
// cube [box, box + box_size) counts. Throws mv::Error past what one dispatch holds.
struct WalkItems {
  std::vector<uint32_t> tri, col, guess;
};
WalkItems walk_items(std::span<const float> tris, uint32_t resolution, const uint32_t box[3], uint32_t box_size);

// What the voxelizer met, for mesh colours: per (triangle, brick) the brick's key, the voxels the triangle sets in
// it and the triangle's index among those added (from 0). Sorted by key when one emission made them all.
struct Fragments {
  std::vector<uint64_t> keys, masks;
  std::vector<uint32_t> tris;
  bool sorted = true;
  uint64_t size() const { return keys.size(); }
};

class Voxelizer {
 public:
  enum class Rule { kConservative, kThin };  // 26-separating exact overlap, or 6-separating (thin)
  Voxelizer(Device& dev, uint32_t resolution, Rule rule = Rule::kConservative);
  Rule rule() const { return rule_; }
  // Keeps only the voxels of the cube [x, x + size) x [y, y + size) x [z, z + size) (out-of-core builds
  // voxelize one such cube at a time). Default: the whole grid.
  void restrict_to(uint32_t x, uint32_t y, uint32_t z, uint32_t size);
  // Host bytes the collected bricks (and the merge that grows them) may take; past it, add() throws an
  // mv::Error naming the need. 0 = no limit.
  void limit_host_memory(uint64_t bytes) { host_budget_ = bytes; }
  // Triangles in grid units (9 floats each), e.g. from triangles_to_grid.
  void add(const std::vector<float>& grid_triangles);
  // The bricks of every voxel an added triangle meets; resets the collection.
  Bricks take_bricks();
  // The same as sorted, unique 64-bit Morton keys of the voxels.
  std::vector<uint64_t> take_keys() { return keys_from_bricks(take_bricks()); }
  // Keep the fragments from here on (20 bytes each on the host, within limit_host_memory).
  void record_fragments() { record_ = true; }
  Fragments take_fragments() { return std::exchange(fragments_, {}); }
  uint64_t triangles() const { return triangles_; }
  uint64_t hits() const { return hits_; }  // (triangle, brick) pairs before merging repeats

 private:
  struct Emission {  // one batch's triangles and work items on the device
    Buffer tris, item_tri, item_col, counter;
    uint32_t first_tri;  // the batch's first triangle among all added
  };
  void emit(Emission& e, uint32_t first, uint32_t last, uint64_t capacity, uint64_t room);
  void merge(Bricks&& chunk);
  void keep_fragments(const std::vector<uint64_t>& keys, const std::vector<uint64_t>& masks, const Buffer& slot_tris,
                      const Buffer& order, uint32_t found);
  Device& dev_;
  uint32_t resolution_;
  Rule rule_;
  uint32_t box_[3] = {0, 0, 0};
  uint32_t box_size_;
  uint64_t triangles_ = 0;
  uint64_t hits_ = 0;
  uint64_t host_budget_ = 0;
  Bricks bricks_;
  bool record_ = false;
  Fragments fragments_;
};

}  // namespace mv
