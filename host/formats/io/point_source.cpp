// open_points (point_source.h): the reader chosen by the file's first bytes.
#include "point_source.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <algorithm>

#include "file_ops.h"
#include "las_reader.h"
#include "megavox/error.h"
#include "ply_points.h"

namespace mv::io {

uint64_t PointSource::skip(uint64_t n) {
  PointColumns scratch;
  const uint64_t end = records_read() + n;
  while (records_read() < end) {
    scratch.clear();
    if (!next(scratch, static_cast<size_t>(std::min<uint64_t>(end - records_read(), uint64_t{1} << 20)))) break;
  }
  return 0;
}

std::unique_ptr<PointSource> open_points(const std::string& path, const PointReadOptions& options) {
  const std::string head = first_bytes(path, 4);
  if (head == "LASF") return open_las(path, options);  // LAS and LAZ alike
  if (head == "ply\n" || head == "ply\r") return open_ply_points(path, options);
  throw Error(path +
              ": not a point cloud megavox reads: a PLY file starts with 'ply', a LAS file with 'LASF' "
              "(LAS 1.0 to 1.4, point formats 0 to 10; LAZ formats 0, 1, 2, 3, 6, 7, 8)");
}

}  // namespace mv::io
