// PointColumns (megavox/points.h): the column operations readers and the LOD builder share.
#include "megavox/points.h"

namespace mv {

void PointColumns::clear() {
  xyz.clear();
  rgb.clear();
  normal.clear();
  intensity.clear();
  extra.clear();
}

void PointColumns::append(const PointColumns& from, uint64_t i, uint32_t extra_bytes) {
  // A column is copied when `from` carries it: its columns are either empty or hold every point.
  auto copy = [i](auto& to, const auto& src, uint64_t per_point) {
    if (src.empty()) return;
    auto first = src.begin() + static_cast<std::ptrdiff_t>(i * per_point);
    to.insert(to.end(), first, first + static_cast<std::ptrdiff_t>(per_point));
  };
  copy(xyz, from.xyz, 3);
  copy(rgb, from.rgb, 3);
  copy(normal, from.normal, 3);
  copy(intensity, from.intensity, 1);
  if (extra_bytes > 0) copy(extra, from.extra, extra_bytes);
}

}  // namespace mv
