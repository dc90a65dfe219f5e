// Plain references of the record gather (megavox/primitives.h gather_records) and of the point bounds
// (points/point_kernels.h point_bounds): byte copies and a min/max loop.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace mv::ref {

// Record i of the result is record index[i] of src, records of record_bytes bytes.
std::vector<uint8_t> gather_records(std::span<const uint8_t> src, std::span<const uint32_t> index, uint32_t record_bytes);

// The min x, y, z then max x, y, z of xyz (3 int32 a point, at least one point).
std::array<int64_t, 6> point_bounds(std::span<const int32_t> xyz);

}  // namespace mv::ref
