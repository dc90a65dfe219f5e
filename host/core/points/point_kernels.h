// Device steps of the point-cloud LOD build (kernels: kernels/common/points.h): Morton codes of the points and
// their sort. The representatives of OMiCroN's inner nodes are omicron_representatives.h's.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "megavox/device.h"
#include "megavox/points.h"
#include "megavox/primitives.h"

namespace mv::points {

// The cube the codes cover, on the input's grid: cell = (xyz - min) >> shift, 21 bits per axis.
struct PointCube {
  int64_t min[3] = {0, 0, 0};
  int32_t shift = 0;  // negative: cells are (xyz - min) << -shift
};

// The smallest power-of-two cube at the points' min corner whose 2^21 cells per axis cover them; clouds narrower
// than 2^21 units are scaled up so that their extent fills the top bit of the cells.
PointCube cube_of(std::span<const int32_t> xyz);
// The same from the points' bounds per axis (lo <= hi).
PointCube cube_of_bounds(const int64_t lo[3], const int64_t hi[3]);
// The points' bounds per axis (at least one point), reduced on the device: each work-item reduces its share of a
// chunk of points, the host the few thousand boxes that leaves.
void point_bounds(Device& dev, std::span<const int32_t> xyz, int64_t lo[3], int64_t hi[3]);
// cube_of_bounds of point_bounds.
PointCube cube_on_device(Device& dev, std::span<const int32_t> xyz);

// A built hierarchy's grid and counts (its nodes, nodes_per_level and points set): every point of `info`'s cloud
// kept, on the cube's grid.
void set_grid_and_counts(PointHierarchy& h, const PointCloudInfo& info, const PointCube& cube, uint32_t grid_bits,
                         uint64_t points);

// codes[i] = the 63-bit Morton code of point i's cell, index[i] = i; computed on the device in chunks.
void point_codes(Device& dev, std::span<const int32_t> xyz, const PointCube& cube, std::vector<uint64_t>& codes,
                 std::vector<uint32_t>& index);

// The codes and index of point_codes, sorted by code (stable), left on the device where the host reads them in
// place (Device::host_view): no host copies of 12 bytes a point, written, uploaded and read back. For CPU
// devices; returns false (nothing kept) where it does not apply: no host view, or the arrays past the device's
// binding limit or budget. The caller then takes point_codes and radix_sort over host vectors (same bytes).
struct SortedCodes {
  Buffer keys, values;
  std::span<const uint64_t> codes;
  std::span<const uint32_t> index;
  SortReport sort;
  double codes_seconds = 0, sort_seconds = 0;
};
// `on_prefix`, when set, gets the sorted codes and index whose first `end` are final while the sort goes on (see
// radix_sort's SortedPrefix, cut into `ranges`), the last time with every point.
using SortedCodesPrefix =
    std::function<void(std::span<const uint64_t> codes, std::span<const uint32_t> index, uint64_t end)>;
bool sorted_codes_in_place(Device& dev, std::span<const int32_t> xyz, const PointCube& cube, SortedCodes& out,
                           const SortedCodesPrefix& on_prefix = {}, uint32_t ranges = 8);

}  // namespace mv::points
