// A point cloud held in the caller's memory (the C API's build from arrays), read in place as a PointSource.
#pragma once
#include <memory>
#include <string>

#include "io/point_source.h"

namespace mv::io {

// Positions go onto the grid a PLY of the same values gets (io/ply_points.h): float32 arrays as float x, y, z,
// float64 as double, offset 0. The arrays must outlive the source. Throws mv::Error (naming `label`) for a
// ragged or missing array or a coordinate that is not finite, before any point is handed out.
std::unique_ptr<PointSource> memory_points(const PointArrays& arrays, const std::string& label);

}  // namespace mv::io
