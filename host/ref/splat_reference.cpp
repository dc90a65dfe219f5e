#include "splat_reference.h"

#include <algorithm>

namespace mv::ref {

void splat_reference(const points::SplatFrame& frame, std::vector<uint32_t>& depth, std::vector<uint32_t>& index) {
  const MvSplatParams& p = frame.params;
  const uint64_t pixels = uint64_t{p.width} * p.height;
  std::vector<uint64_t> best(pixels, ~uint64_t{0});  // key << 32 | index: the lexicographic minimum
  const int64_t r = p.radius;
  for (uint64_t i = 0; i < frame.cells.size() / 3; ++i) {
    const MvSplatHit hit = mv_splat_project(frame.cells[3 * i], frame.cells[3 * i + 1], frame.cells[3 * i + 2], p);
    if (!hit.visible) continue;
    const uint64_t pair = (uint64_t{hit.key} << 32) | i;
    for (int64_t y = hit.py - r; y <= hit.py + r; ++y)
      for (int64_t x = hit.px - r; x <= hit.px + r; ++x)
        if (x >= 0 && y >= 0 && x < p.width && y < p.height) {
          uint64_t& b = best[uint64_t(y) * p.width + uint64_t(x)];
          b = std::min(b, pair);
        }
  }
  depth.assign(pixels, MV_SPLAT_EMPTY);
  index.assign(pixels, MV_SPLAT_EMPTY);
  for (uint64_t q = 0; q < pixels; ++q)
    if (best[q] != ~uint64_t{0}) {
      depth[q] = static_cast<uint32_t>(best[q] >> 32);
      index[q] = static_cast<uint32_t>(best[q]);
    }
}

}  // namespace mv::ref
