// Gathers point columns by an index list (the sort's permutation, the hierarchy's node order).
#pragma once
#include <cstdint>
#include <span>

#include "megavox/points.h"
#include "omicron.h"

namespace mv::points {

// out point i = src point index[i], every column src carries.
PointColumns gather_columns(const PointColumns& src, std::span<const uint64_t> index, uint32_t extra_bytes);
PointColumns gather_columns(const PointColumns& src, std::span<const uint32_t> index, uint32_t extra_bytes);

// The columns of sorted points into node order (OmicronBuilder::assemble's sources, with its reps): a leaf's
// points are one block copy, a representative one read each.
PointColumns gather_node_points(const PointColumns& sorted, std::span<const NodePoints> sources,
                                std::span<const uint64_t> reps, uint32_t extra_bytes);

}  // namespace mv::points
