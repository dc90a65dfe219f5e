// Plain C++ references of the point-cloud LOD build (host/core/points/): the representatives of a level's parents,
// and the whole hierarchy built top-down by recursive splitting, a different algorithm from the streaming
// bottom-up build, which the tests compare byte for byte.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "megavox/points.h"

namespace mv::ref {

// Positions in `codes` of the representatives of each parent, parent by parent (points_kernels.h's rule).
std::vector<uint32_t> representatives(std::span<const uint64_t> codes, std::span<const uint32_t> bounds,
                                      uint32_t cell_bits, uint32_t cap);

struct PointLodRule {
  uint32_t depth = 0;            // the leaf level
  uint32_t max_node_points = 0;  // a node whose subtree holds at most this many points is a leaf; caps representatives
  uint32_t grid_bits = 6;        // an inner node at level l picks one point per cell of level l + grid_bits
};

// The hierarchy of `points` (not yet sorted) under `rule`.
PointHierarchy build_point_hierarchy(const PointColumns& points, const PointCloudInfo& info, const PointLodRule& rule);

}  // namespace mv::ref
