// Plain C++ reference implementations: the oracle every kernel's test compares against. Written for
// obviousness, not speed, and apart from the kernels: each walks the whole problem its own plain way (every
// voxel of a box, plain maps, one sort). Where bytes must match a kernel's exactly, a reference shares the one
// decisive predicate on purpose and says so (voxelize: kernels/common/voxelize.h's mv_voxel_hit and
// mv_voxel_floor), so that a test checks the kernel's traversal of the problem, not float rounding.
#pragma once
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace mv::ref {

// Bit i of x, y, z -> bits 3i, 3i+1, 3i+2; `bits_per_axis` = 21 (64-bit keys) or 10 (32-bit keys).
uint64_t morton3(uint32_t x, uint32_t y, uint32_t z, int bits_per_axis);

// Sorted unique Morton keys of the voxels the triangles (grid units, 9 floats each) meet: every voxel of each
// triangle's bounding box is tested with the decisive predicate the kernels use (kernels/common/voxelize.h),
// without the kernels' column walk. `thin`: the 6-separating rule instead of the conservative one.
std::vector<uint64_t> voxelize(const std::vector<float>& grid_triangles, uint32_t resolution, bool thin = false);

// Node counts per level (index = level; level 0 = voxels) of the sparse octree of sorted unique voxel keys
// in a 2^levels grid, and of its minimal DAG, from plain maps keyed by (mask, child ids).
struct DagCounts {
  std::vector<uint64_t> svo, dag;
};
DagCounts dag_counts(const std::vector<uint64_t>& voxels, uint32_t levels);

// The same for the DAG reduced up to the 8 axis reflections (SSVDAG, exact stabilizer method), written
// independently of the kernels: class keys are vectors of (mask, then (child id, normalized tag) per octant).
DagCounts ssvdag_counts(const std::vector<uint64_t>& voxels, uint32_t levels);

// out[i] = sum of in[0..i), out[n] = total.
std::vector<uint32_t> exclusive_scan(const std::vector<uint32_t>& in);
// The same in 64 bits, from `start`.
std::vector<uint64_t> exclusive_scan64(const std::vector<uint32_t>& in, uint64_t start = 0);

// The sorted keys with each run of equal keys kept once.
std::vector<uint64_t> unique_sorted(const std::vector<uint64_t>& sorted);

// std::stable_sort of (key, value) pairs by key; values may be null (keys only).
template <class Key>
void stable_sort(std::vector<Key>& keys, std::vector<uint32_t>* values) {
  if (!values) {
    std::stable_sort(keys.begin(), keys.end());
    return;
  }
  std::vector<uint32_t> order(keys.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
  std::vector<Key> k(keys.size());
  std::vector<uint32_t> v(keys.size());
  for (size_t i = 0; i < order.size(); ++i) {
    k[i] = keys[order[i]];
    v[i] = (*values)[order[i]];
  }
  keys.swap(k);
  values->swap(v);
}

}  // namespace mv::ref
