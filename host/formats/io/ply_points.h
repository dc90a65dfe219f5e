// PLY point reader: the `vertex` element of a PLY 1.0 file (ascii, binary little or big endian) as points,
// through the PLY mesh reader's header parser and value readers. Other elements (faces, ...) are skipped.
//
// Vertex properties read (any other is skipped):
// - x, y, z, of any scalar type (required);
// - red, green, blue (or r, g, b, or diffuse_red, diffuse_green, diffuse_blue) -> kPointRgb: integer values as
//   stored (uchar 0-255 stays 0-255, ushort as is), clamped to [0, 65535]; float values are fractions of 1,
//   stored as 0-255;
// - nx, ny, nz (or normal_x, normal_y, normal_z) -> kPointNormal, as float;
// - intensity (or scalar_intensity, scalar_Intensity) -> kPointIntensity, rounded and clamped to [0, 65535].
// Colours and normals are read when all three properties are there; a partial set is skipped.
//
// The grid: positions become int32, world = scale * X (offset 0, the same scale on every axis). A first
// streaming pass finds M, the largest |coordinate| over all axes, and refuses a NaN or infinite coordinate,
// naming its vertex. With e such that 2^(e-1) <= M < 2^e:
// - integer x, y, z and M < 2^31: scale 1, exact;
// - float x, y, z (or integers of at most 16 bits among floats): scale 2^(e-24), float32's ulp at the largest
//   magnitude, so the largest values are exact and |X| <= 2^24;
// - double, or 32-bit integers among floats, or integers from 2^31: scale 2^(e-30), |X| <= 2^30;
// - all coordinates 0: scale 1.
// X = llround(c / scale): the world coordinate is within scale / 2 of the file's. The second pass streams the
// points in batches. +Y is up (z_up false). Internal to host/io (open_points chooses it); not a public API.
#pragma once
#include <memory>
#include <string>

#include "point_source.h"

namespace mv::io {

// The precision rule's cases, above.
enum class PlyGrid { integer, float32, float64 };

// The scale of the grid for positions of kind `grid` whose largest |coordinate| is `max_abs`.
double ply_grid_scale(PlyGrid grid, double max_abs);

std::unique_ptr<PointSource> open_ply_points(const std::string& path, const PointReadOptions& options);

}  // namespace mv::io
