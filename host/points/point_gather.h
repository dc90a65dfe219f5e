// Gathers point columns by an index list (the sort's permutation, the hierarchy's node order).
#pragma once
#include <cstdint>
#include <span>

#include "megavox/points.h"

namespace mv::points {

// out point i = src point index[i], every column src carries.
PointColumns gather_columns(const PointColumns& src, std::span<const uint64_t> index, uint32_t extra_bytes);
PointColumns gather_columns(const PointColumns& src, std::span<const uint32_t> index, uint32_t extra_bytes);

}  // namespace mv::points
