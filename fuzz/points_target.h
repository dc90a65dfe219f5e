// The body of fuzz_ply_points, fuzz_las and fuzz_laz: open_points (host/formats/io/point_source.h) and every point. Both take
// any content (the reader is chosen by the first bytes); they differ in their seeds and the file's name.
#pragma once
#include <vector>

#include "fuzz_support.h"
#include "io/point_source.h"
#include "megavox/error.h"

namespace mv::fuzz {

inline int read_points(const uint8_t* data, size_t size, const char* suffix) {
  const std::string& path = memory_input(data, size, suffix);
  // The input's size picks the options: odd sizes a 64-byte LAS read buffer, every other pair of sizes
  // without the extra bytes; batches of 1 to 97 points.
  io::PointReadOptions options;
  options.ram_bytes = size % 2 ? 64 : UINT64_MAX;
  options.carry_extra_bytes = size / 2 % 2 == 0;
  options.threads = 1 + size / 4 % 2;  // LAZ: chunks decoded on one thread or two
  const size_t batch = 1 + size % 97;
  try {
    auto source = io::open_points(path, options);
    const PointCloudInfo& info = source->info();
    PointColumns points;
    uint64_t total = 0;
    while (true) {
      points.clear();
      if (!source->next(points, batch)) {
        MV_FUZZ_CHECK(points.size() == 0);
        break;
      }
      const uint64_t n = points.size();
      MV_FUZZ_CHECK(n >= 1 && n <= batch && points.xyz.size() == 3 * n);
      MV_FUZZ_CHECK(points.rgb.size() == (info.attributes & kPointRgb ? 3 * n : 0));
      MV_FUZZ_CHECK(points.normal.size() == (info.attributes & kPointNormal ? 3 * n : 0));
      MV_FUZZ_CHECK(points.intensity.size() == (info.attributes & kPointIntensity ? n : 0));
      MV_FUZZ_CHECK(points.extra.size() == (info.attributes & kPointExtra ? n * info.extra_bytes : 0));
      total += n;
    }
    MV_FUZZ_CHECK(total == info.points);
  } catch (const Error&) {
  }
  return 0;
}

}  // namespace mv::fuzz
