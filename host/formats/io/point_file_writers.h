// Point clouds written from any point source (io/point_source.h), in the source's order: what `points convert`
// writes when the output is PLY, or LAS from a PLY cloud. (LAS and LAZ to LAS keep every record byte for byte
// through io/las_convert.h instead.)
//
// - PLY 1.0, binary little-endian: x, y, z as double (world units: offset + scale * X), then where the source
//   has them nx, ny, nz (float), red, green, blue (ushort), intensity (ushort) and every named field of the
//   attribute record (megavox/points.h PointField) as a property of its own type (64-bit integers as double,
//   an array as NAME_0, NAME_1, ...; scale and add not applied); the source format and CRS as comments.
// - LAS 1.4 point format 6 (7 with colour): the source's grid as the header's scale and offset (a PLY cloud's
//   chosen grid, docs/points.md), intensity, the LAS fields a LAS source names (classification, returns, GPS
//   time, ...), and normals as extra bytes described by an Extra Bytes record (nx, ny, nz).
// Both are written atomically (io/atomic_file.h) to an output resolved by the caller. mv::Error names the file.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include "point_source.h"

namespace mv::io {

// Writes every point `source` delivers; returns how many. `progress(points done)` after each batch.
uint64_t write_ply_points(PointSource& source, const std::string& output,
                          const std::function<void(uint64_t)>& progress = {});
uint64_t write_las_points(PointSource& source, const std::string& output,
                          const std::function<void(uint64_t)>& progress = {});

}  // namespace mv::io
