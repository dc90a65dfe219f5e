// Gathers point columns by an index list (the sort's permutation, the hierarchy's node order).
#pragma once
#include <cstdint>
#include <span>

#include "megavox/device.h"
#include "megavox/points.h"
#include "omicron.h"

namespace mv::points {

// out point i = src point index[i], every column src carries.
// out point i = src point index[i], every column src carries (on the host).
PointColumns gather_columns(const PointColumns& src, std::span<const uint64_t> index, uint32_t extra_bytes);
PointColumns gather_columns(const PointColumns& src, std::span<const uint32_t> index, uint32_t extra_bytes);

// out record i = src record index[i], records of record_bytes bytes (one column of any kind, on the host).
void gather_record_bytes(const uint8_t* src, uint32_t record_bytes, std::span<const uint32_t> index, uint8_t* out);

// The columns of sorted points into node order (OmicronBuilder::assemble's sources, with its reps), on the host:
// a leaf's points are one block copy, a representative one read each.
PointColumns gather_node_points(const PointColumns& sorted, std::span<const NodePoints> sources,
                                std::span<const uint64_t> reps, uint32_t extra_bytes);

// The columns of the points (input order) in node order on the device: each column gathered once through the
// composed index (node order -> sorted position -> input position, `index` being the sort's permutation), a
// column past one device binding in slices of it, the output in chunks. A column the device's memory cannot hold
// is gathered on the host the same way (the same bytes). Each input column is freed once gathered, so that the
// next output column reuses its memory. chunk_records and slice_records (0: the defaults) are for tests, which
// shrink them to put seams anywhere.
PointColumns gather_node_points(Device& dev, PointColumns&& points, std::span<const uint32_t> index,
                                std::span<const NodePoints> sources, std::span<const uint64_t> reps,
                                uint32_t extra_bytes, uint64_t chunk_records = 0, uint64_t slice_records = 0);

}  // namespace mv::points
