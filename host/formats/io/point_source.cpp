// open_points (point_source.h): the reader chosen by the file's first bytes.
#include "point_source.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "las_header.h"
#include "file_ops.h"
#include "las_reader.h"
#include "megavox/error.h"
#include "ply_points.h"

namespace mv::io {

namespace {

bool ends_with_laz(std::string path) {
  std::transform(path.begin(), path.end(), path.begin(), [](unsigned char c) { return std::tolower(c); });
  return path.size() >= 4 && path.compare(path.size() - 4, 4, ".laz") == 0;
}

}  // namespace

std::unique_ptr<PointSource> open_points(const std::string& path, const PointReadOptions& options) {
  const std::string head = first_bytes(path, 4);
  if (head == "LASF") return open_las(path, options);  // refuses LAZ itself, by its header or its name
  if (head == "ply\n" || head == "ply\r") return open_ply_points(path, options);
  if (ends_with_laz(path)) throw Error(detail::laz_message(path));
  throw Error(path +
              ": not a point cloud megavox reads: a PLY file starts with 'ply', a LAS file with 'LASF' "
              "(uncompressed LAS 1.0 to 1.4, point formats 0, 1, 2, 3, 6, 7, 8)");
}

}  // namespace mv::io
