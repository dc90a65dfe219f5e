// megavox — voxels from point clouds, with their colours in depth-first order (docs/colour.md).
//
// A cloud's points, already on the grid as integer cells, become the set of voxels they fall in (sorted unique
// Morton codes) and, when they carry colour, the attribute array: one RGB24 entry per octree node, voxels and
// inner nodes alike, in pre-order (children in Morton octant order), so DAG node counts do not change with
// colour. A voxel's colour is the mean of its points' 8-bit channels, an inner node's the mean of the voxel
// colours below it (sum / count), each rounded half up. Runs on the device: Morton codes, the radix sort, the
// segmentation, the segmented sums and the scan are the shared primitives; kernels/common/colour.h adds the
// colour packed into the sort key, the divides, and every node's range and place in depth-first order.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "megavox/colour_quantize.h"
#include "megavox/dag_types.h"
#include "megavox/device.h"

namespace mv {

struct CloudVoxels {
  std::vector<uint64_t> keys;    // the voxels: sorted unique 64-bit Morton codes of a 2^levels grid
  std::vector<uint8_t> colours;  // RGB24 per octree node in pre-order (empty without colour)
};

// cells: x, y, z per point, each below 2^levels (1 <= levels <= 21); rgb: 0xBBGGRR per point, or empty for no
// colour. Throws mv::Error when the points pass what one device call holds (2^28 points with colour, 2^31
// without) or the octree has 2^32 nodes or more (the attribute array's 32-bit indices).
// `colour_seconds`, when given, receives the time spent on the colours (included in the call's).
// The inner nodes' means come from prefix sums of the voxels' channels: 32-bit ones (exact mod 2^32) below
// 2^32 / 255 voxels, 64-bit past that; `wide` takes 64-bit ones always (the same bytes; for tests).
enum class ColourSums { automatic, wide };
CloudVoxels voxelize_cloud(Device& dev, std::span<const uint32_t> cells, std::span<const uint32_t> rgb,
                           uint32_t levels, double* colour_seconds = nullptr,
                           ColourSums width = ColourSums::automatic);

// The depth-first colours of voxels with one colour each (a mesh's: host/core/voxel/mesh_colours.cpp): voxel_keys
// sorted unique codes and voxel_rgb 0xBBGGRR in the same order, both on the device; inner nodes get the means
// of the voxels below them, as for clouds.
std::vector<uint8_t> depth_first_voxel_colours(Device& dev, Buffer voxel_keys, const Buffer& voxel_rgb, uint64_t voxels,
                                               uint32_t levels, ColourSums width = ColourSums::automatic);

// The number of octree nodes in the subtree of every DAG node (itself included, voxels counted as nodes), by
// level and node id: sizes[l][i] for l >= 1 (level 1: 1 + its voxels). A mirrored subtree has the size of the
// stored one, so one number per DAG node serves every instance.
std::vector<std::vector<uint64_t>> subtree_sizes(const Dag& dag);

// Every octree node a traversal of `dag` meets, at the depth-first attribute index recovered from subtree
// sizes alone: visit(index, level, Morton code of the node at its level). An SSVDAG's reflections are followed:
// the child shown at octant a of a node seen mirrored by T is the stored child at a ^ T, so the sizes are
// summed in the order the octants are shown, not stored. Nodes come in pre-order.
void for_each_attribute_index(const Dag& dag,
                              const std::function<void(uint64_t index, uint32_t level, uint64_t code)>& visit);

// A Lloyd round's assignment on `dev` (kernels/common/quantize.h), the answers of nearest_centres_on_host.
NearestCentres nearest_centres_on(Device& dev);
// quantize_colours (megavox/colour_quantize.h) with each round's nearest centres found on `dev` (on the host for a
// CPU-shaped device that computes in host memory): the same palette and colours, byte for byte.
ColourQuantizeReport quantize_colours(Device& dev, std::vector<uint8_t>& rgb, uint32_t bits);

}  // namespace mv
